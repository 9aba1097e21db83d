#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/slam_config.hpp"

namespace cleanslam::slam_core {

// The map's management for both kinds of frame: which landmark slot a sighting belongs to (a
// feature's track id, or the front end's tracker slot), undelayed initialization (eq. 39-45),
// deletion, the cap on landmarks in view, re-initialization of a landmark predicted behind the
// camera, and the re-sighting of a landmark after the pose was lost (it is mapped again from its
// ray and merged into its earlier entry, Ekf::merge_landmarks). Allocates nothing.
class MapManager {
 public:
  // At most this many landmarks are observed in one frame.
  static constexpr int kMaxInView = hal::kMaxObservationsPerFrame;
  // The track of a landmark the front end's tracker follows by its slot.
  static constexpr std::int64_t kTrackerSlot = -2;

  // What a sighting of a mapped (or unmapped) track is to become.
  enum class Sighting : std::uint8_t {
    kObserve,  // an update of its landmark
    kNew,      // a new landmark (earlier: its earlier entry to merge into, or -1)
  };

  // A remapped landmark's fate (merge_remapped).
  struct Merge {
    std::int64_t track = -1;
    int slot = -1;  // the kept slot when merged, the remapped one when the merge was gated
    bool merged = false;
    double test_ratio = -1.0;  // Ekf::last_merge_test_ratio
  };

  MapManager(Ekf& ekf, const MapConfig& config);

  // A new map: no slot is owned.
  void forget();
  // The slot the track's landmark occupies, or -1.
  [[nodiscard]] int slot_of(std::int64_t track) const;
  [[nodiscard]] std::int64_t owner(int slot) const {
    return owner_[static_cast<std::size_t>(slot)];
  }
  // Starts a frame with this many of its sightings on mapped landmarks: with more than
  // MapConfig::remap_max_mapped_in_view they constrain the whole pose, and nothing is remapped.
  void begin_frame(int mapped_in_view);
  // Decides a sighting of a track whose landmark is `slot` (-1: none).
  Sighting classify(int slot, int& earlier);
  // How many new landmarks a frame with `observed` landmarks observed may take.
  [[nodiscard]] static int new_landmark_budget(int observed) { return kMaxInView - observed; }
  // Undelayed initialization of the track's landmark at a pixel; `earlier` (or -1) is the entry
  // it maps again. Returns the slot or -1.
  int initialize(std::int64_t track, double u_px, double v_px, int earlier);
  // The landmark is gone (deleted by the caller's policy).
  void remove(int slot);
  // Merges the remapped landmarks whose depth relative to the camera has converged (the young
  // test's fraction) or that were not observed this frame (`observed`); merges() lists them.
  void merge_remapped(std::span<const Observation> observed);
  [[nodiscard]] int merge_count() const { return merge_count_; }
  [[nodiscard]] const Merge& merge(int i) const { return merges_[static_cast<std::size_t>(i)]; }
  // Every landmark becomes dormant: kept, but not where the pose says (the robot was carried)
  // until the pose is found again against them (wake()).
  void set_dormant();
  void wake();
  [[nodiscard]] bool dormant(int slot) const { return dormant_[static_cast<std::size_t>(slot)]; }
  [[nodiscard]] int dormant_count() const { return dormant_count_; }
  // The slot maps again the landmark in `earlier()` (merged in later), or -1.
  [[nodiscard]] int earlier(int slot) const {
    return merge_target_[static_cast<std::size_t>(slot)];
  }

 private:
  [[nodiscard]] bool needs_remap(int slot) const;

  Ekf& ekf_;
  MapConfig config_;
  std::array<std::int64_t, hal::kMaxLandmarks> owner_{};  // track per slot, -1: free
  std::array<int, hal::kMaxLandmarks> merge_target_{};    // earlier entry of a remapped slot
  bool remap_allowed_ = false;
  std::array<bool, hal::kMaxLandmarks> dormant_{};
  int dormant_count_ = 0;
  std::array<Merge, hal::kMaxLandmarks> merges_{};
  int merge_count_ = 0;
};

}  // namespace cleanslam::slam_core
