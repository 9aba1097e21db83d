#include "cleanslam/slam_core/map_manager.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

namespace cleanslam::slam_core {

MapManager::MapManager(Ekf& ekf, const MapConfig& config) : ekf_(ekf), config_(config) {
  forget();
}

void MapManager::forget() {
  owner_.fill(-1);
  merge_target_.fill(-1);
  merge_count_ = 0;
  remap_allowed_ = false;
  wake();
}

void MapManager::set_dormant() {
  dormant_count_ = 0;
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    dormant_[static_cast<std::size_t>(s)] = ekf_.slot_used(s);
    dormant_count_ += ekf_.slot_used(s) ? 1 : 0;
  }
}

void MapManager::wake() {
  dormant_.fill(false);
  dormant_count_ = 0;
}

int MapManager::slot_of(std::int64_t track) const {
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    if (owner_[static_cast<std::size_t>(s)] == track && ekf_.slot_used(s)) {
      return s;
    }
  }
  return -1;
}

void MapManager::begin_frame(int mapped_in_view) {
  remap_allowed_ = mapped_in_view <= config_.remap_max_mapped_in_view;
  merge_count_ = 0;
}

MapManager::Sighting MapManager::classify(int slot, int& earlier) {
  earlier = -1;
  if (slot < 0 || needs_remap(slot)) {
    earlier = slot;
    return Sighting::kNew;
  }
  return Sighting::kObserve;
}

int MapManager::initialize(std::int64_t track, double u_px, double v_px, int earlier) {
  const int slot = ekf_.initialize_landmark(u_px, v_px);
  if (slot < 0) {
    return -1;
  }
  const auto s = static_cast<std::size_t>(slot);
  owner_[s] = track == kTrackerSlot ? slot : track;
  if (dormant_[s]) {  // a dormant landmark replaced (a full pool)
    dormant_[s] = false;
    --dormant_count_;
  }
  // The slot may be a recycled one (a full pool): no merge may refer to what it held.
  merge_target_[s] = -1;
  std::replace(merge_target_.begin(), merge_target_.end(), slot, -1);
  if (earlier >= 0 && earlier != slot && ekf_.slot_used(earlier)) {
    owner_[static_cast<std::size_t>(earlier)] = -1;
    merge_target_[s] = earlier;
  }
  return slot;
}

void MapManager::remove(int slot) {
  if (slot < 0 || slot >= hal::kMaxLandmarks) {
    return;
  }
  owner_[static_cast<std::size_t>(slot)] = -1;
  merge_target_[static_cast<std::size_t>(slot)] = -1;
  if (dormant_[static_cast<std::size_t>(slot)]) {
    dormant_[static_cast<std::size_t>(slot)] = false;
    --dormant_count_;
  }
  std::replace(merge_target_.begin(), merge_target_.end(), slot, -1);
}

// Only with the heading lost: with a known pose a poor prediction is the landmark's own doing.
bool MapManager::needs_remap(int slot) const {
  const double limit = config_.remap_pixel_std_px;
  if (!(limit > 0.0) || !remap_allowed_ || merge_target_[static_cast<std::size_t>(slot)] >= 0) {
    return false;
  }
  if (!(std::sqrt(std::max(0.0, ekf_.pose_covariance()(5, 5))) >
        config_.remap_min_yaw_std_deg * std::numbers::pi / 180.0)) {
    return false;
  }
  PixelPrediction pp;
  if (!ekf_.predict_pixel(slot, pp) || !pp.in_front) {
    return true;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(pp.S, Eigen::EigenvaluesOnly);
  return !(std::sqrt(std::max(0.0, eig.eigenvalues()(1))) <= limit);
}

void MapManager::merge_remapped(std::span<const Observation> observed) {
  merge_count_ = 0;
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    const auto ss = static_cast<std::size_t>(s);
    const int earlier = merge_target_[ss];
    if (earlier < 0) {
      continue;
    }
    if (!ekf_.slot_used(s) || !ekf_.slot_used(earlier)) {
      merge_target_[ss] = -1;
      continue;
    }
    const bool seen = std::any_of(observed.begin(), observed.end(),
                                  [s](const Observation& o) { return o.slot == s; });
    const double rel = ekf_.relative_depth_std(s);
    if (seen && !(rel >= 0.0 && rel < ekf_.config().young_depth_std_fraction)) {
      continue;
    }
    Merge& m = merges_[static_cast<std::size_t>(merge_count_++)];
    m.track = owner_[ss];
    merge_target_[ss] = -1;
    // No gate: the track id says that both entries are the same point.
    m.merged = ekf_.merge_landmarks(earlier, s, 0.0) == ObservationResult::kFused;
    m.test_ratio = ekf_.last_merge_test_ratio();
    if (m.merged) {
      owner_[static_cast<std::size_t>(earlier)] = m.track;
      owner_[ss] = -1;
      m.slot = earlier;
    } else {
      ekf_.delete_landmark(earlier);
      m.slot = s;
    }
  }
}

}  // namespace cleanslam::slam_core
