#pragma once

#include <array>
#include <cstdint>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/slam_core/frontend/harris.hpp"

namespace cleanslam::slam_core::frontend {

struct LandmarkBookConfig {
  // A landmark predicted inside the image that fails this many frames in a row is deleted.
  int max_consecutive_failures = 3;
  // A landmark matched fewer times than this since its initialization is deleted at its first
  // frame without a match, in view or not: its depth is still unknown, and found again later its
  // wide search region easily takes a look-alike for it.
  int min_matches_to_keep = 3;
  // New landmarks are taken when fewer than min_in_view were matched, up to target_in_view
  // (Section 3.2: 5-10 landmarks in view).
  int min_in_view = 5;
  int target_in_view = 10;
  // New landmarks keep this distance from every landmark in view, in pixels.
  double exclusion_px = 20.0;
};

// The front end's record of the map's landmark slots: which are active and how often each has
// failed in a row.
class LandmarkBook {
 public:
  explicit LandmarkBook(const LandmarkBookConfig& config = {}) : config_(config) {}

  void activate(int slot);
  void remove(int slot);
  // Active again after a long gap (relocalized against the map): no longer young, and not
  // matched for long (Tracker::track's reacquisition).
  void resume(int slot);
  [[nodiscard]] bool active(int slot) const;
  [[nodiscard]] int active_count() const { return active_count_; }
  // Records a frame's outcome for a landmark searched in it; returns true when the landmark has
  // now failed max_consecutive_failures times in a row and should be deleted.
  bool record(int slot, bool matched);
  [[nodiscard]] int failures(int slot) const;
  // Starts a frame (for frames_since_match).
  void next_frame() { ++frame_; }
  // Frames since the landmark's last match (or activation).
  [[nodiscard]] int frames_since_match(int slot) const;
  // Frames in which the landmark was matched since its activation.
  [[nodiscard]] int matches(int slot) const;
  // Still young (fewer than min_matches_to_keep matches): deleted at its first miss.
  [[nodiscard]] bool young(int slot) const { return matches(slot) < config_.min_matches_to_keep; }
  [[nodiscard]] const LandmarkBookConfig& config() const { return config_; }

 private:
  LandmarkBookConfig config_;
  std::array<bool, hal::kMaxLandmarks> active_{};
  std::array<std::uint16_t, hal::kMaxLandmarks> failures_{};
  std::array<std::uint16_t, hal::kMaxLandmarks> matches_{};
  std::array<std::uint32_t, hal::kMaxLandmarks> last_match_{};
  std::uint32_t frame_ = 0;
  int active_count_ = 0;
};

// Section 3.2: the strongest corners (the list is strongest first) that are at least
// exclusion_px from every occupied pixel (landmarks in view), from each other, and at least
// `margin_px` inside the image. Writes up to max_out indices into `out`; returns the count.
int select_new_corners(const Corner* corners, int corner_count, const double* occupied_u,
                       const double* occupied_v, int occupied_count, double exclusion_px, int width,
                       int height, int margin_px, int max_out, int* out);

}  // namespace cleanslam::slam_core::frontend
