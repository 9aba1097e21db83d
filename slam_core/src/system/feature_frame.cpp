// SlamSystem's frames with pixel observations and track ids.
#include <span>

#include "cleanslam/slam_core/slam_system.hpp"

namespace cleanslam::slam_core {

namespace lf = hal::log;

namespace {

lf::UpdateStatus record_status(ObservationResult r) {
  switch (r) {
    case ObservationResult::kFused:
      return lf::UpdateStatus::kUpdated;
    case ObservationResult::kGate:
      return lf::UpdateStatus::kGated;
    case ObservationResult::kDepthBound:
      return lf::UpdateStatus::kDepthBound;
    case ObservationResult::kBehindCamera:
      return lf::UpdateStatus::kBehindCamera;
    default:
      return lf::UpdateStatus::kRejected;
  }
}

}  // namespace

// Association, JCBB and the start of one batch update; the update's rest in bounded parts (one
// per call); then the records, the merges of remapped landmarks and the initializations.
bool SlamSystem::step_features(int& budget) {
  if (!fusing_) {
    budget -= frame_.feature_count;
    if (!frame_.has_features()) {
      return true;
    }
    // Usually a no-op: the caller predicted up to the newest encoder sample, at or after it.
    predict(frame_.t_ns + camera_offset_ns_);
    if (!associate_features()) {
      return true;
    }
    fusing_ = true;
    if (ekf_.update_pending()) {
      return false;
    }
  } else if (!ekf_.continue_update()) {
    return false;
  }
  fusing_ = false;
  record_features_update();
  map_.merge_remapped(
      std::span<const Observation>(obs_.data(), static_cast<std::size_t>(obs_count_)));
  record_merges();
  initialize_features();
  return true;
}

bool SlamSystem::associate_features() {
  const int n = frame_.feature_count;
  if (dr_.standing_still()) {
    for (int i = 0; i < n; ++i) {
      record(frame_.features[i], lf::UpdateStatus::kSkipped,
             map_.slot_of(frame_.features[i].track_id));
    }
    return false;
  }
  const double w = calibration_.camera.width;
  const double h = calibration_.camera.height;
  int mapped = 0;
  for (int i = 0; i < n; ++i) {
    feature_slot_[static_cast<std::size_t>(i)] = map_.slot_of(frame_.features[i].track_id);
    mapped += feature_slot_[static_cast<std::size_t>(i)] >= 0 ? 1 : 0;
  }
  map_.begin_frame(mapped);
  int m = 0;
  int fresh = 0;
  for (int i = 0; i < n; ++i) {
    const hal::FeatureObservation& f = frame_.features[i];
    if (!(f.u_px >= -0.5 && f.u_px < w - 0.5 && f.v_px >= -0.5 && f.v_px < h - 0.5)) {
      record(f, lf::UpdateStatus::kRejected, -1);
      continue;
    }
    const int slot = feature_slot_[static_cast<std::size_t>(i)];
    int earlier = -1;
    if (map_.classify(slot, earlier) != MapManager::Sighting::kObserve) {
      remap_of_[static_cast<std::size_t>(fresh)] = earlier;
      new_feature_[static_cast<std::size_t>(fresh++)] = i;
      continue;
    }
    PixelPrediction pp;
    if (m >= kMaxObs || !ekf_.predict_pixel(slot, pp) || !pp.in_front) {
      record(f,
             m < kMaxObs && !pp.in_front ? lf::UpdateStatus::kBehindCamera
                                         : lf::UpdateStatus::kRejected,
             slot);
      continue;
    }
    obs_[static_cast<std::size_t>(m)] = Observation{slot, f.u_px, f.v_px};
    obs_feature_[static_cast<std::size_t>(m)] = i;
    ++m;
  }
  obs_count_ = m;
  fresh_count_ = fresh;
  innovation_count_ = -1;
  jcbb_result_ = frontend::JcbbResult{};
  updated_ = false;
  if (m == 0) {
    return true;
  }
  innovation_count_ = ekf_.joint_pixel_innovation(
      std::span<const Observation>(obs_.data(), static_cast<std::size_t>(m)), nu_, S_);
  if (innovation_count_ == m) {
    jcbb_result_ = jcbb_.solve(nu_.data(), S_.data(), m, inlier_.data());
  }
  int q = 0;
  if (jcbb_result_.update) {
    for (int i = 0; i < m; ++i) {
      if (inlier_[static_cast<std::size_t>(i)]) {
        inlier_obs_[static_cast<std::size_t>(q++)] = obs_[static_cast<std::size_t>(i)];
      }
    }
  }
  if (q > 0) {
    ekf_.update(inlier_obs_.data(), q);
    updated_ = true;
  }
  return true;
}

void SlamSystem::record_features_update() {
  const int m = obs_count_;
  const int k = innovation_count_;
  const bool jcbb_update = jcbb_result_.update;
  const UpdateStatus* status = updated_ ? &ekf_.last_update() : nullptr;
  int next_inlier = 0;
  for (int i = 0; i < m; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    const hal::FeatureObservation& f = frame_.features[obs_feature_[ui]];
    lf::UpdateStatus st = lf::UpdateStatus::kSkipped;  // too few inliers
    if (k != m) {
      st = lf::UpdateStatus::kRejected;
    } else if (jcbb_update && !inlier_[ui]) {
      st = lf::UpdateStatus::kGated;  // JCBB
    } else if (jcbb_update && status != nullptr) {
      const auto& o = status->observations[static_cast<std::size_t>(next_inlier++)];
      st = record_status(o.result);
    }
    record(f, st, obs_[ui].slot);
    if (k == m) {
      lf::UpdateRecord& r = records_[static_cast<std::size_t>(record_count_ - 1)];
      const double nu_u = nu_[2 * ui];
      const double nu_v = nu_[2 * ui + 1];
      const std::size_t ld = 2 * static_cast<std::size_t>(m);
      const double a = S_[2 * ui * ld + 2 * ui];
      const double b = S_[(2 * ui + 1) * ld + 2 * ui];
      const double d = S_[(2 * ui + 1) * ld + 2 * ui + 1];
      const double det = a * d - b * b;
      r.innovation_u = nu_u;
      r.innovation_v = nu_v;
      r.mahalanobis2 =
          det > 0.0 ? (d * nu_u * nu_u - 2.0 * b * nu_u * nu_v + a * nu_v * nu_v) / det : 0.0;
    }
  }
}

void SlamSystem::record_merges() {
  for (int i = 0; i < map_.merge_count(); ++i) {
    const MapManager::Merge& m = map_.merge(i);
    const int before = record_count_;
    record(hal::FeatureObservation{m.track, 0.0, 0.0},
           m.merged ? lf::UpdateStatus::kMerged : lf::UpdateStatus::kMergeGated, m.slot);
    if (record_count_ > before && m.test_ratio >= 0.0) {
      records_[static_cast<std::size_t>(before)].mahalanobis2 = m.test_ratio;
    }
  }
}

// Undelayed initialization of unseen tracks, within the cap on landmarks in view.
void SlamSystem::initialize_features() {
  int budget = MapManager::new_landmark_budget(obs_count_);
  for (int j = 0; j < fresh_count_; ++j) {
    const hal::FeatureObservation& f = frame_.features[new_feature_[static_cast<std::size_t>(j)]];
    if (budget <= 0) {
      record(f, lf::UpdateStatus::kSkipped, -1);
      continue;
    }
    const int slot =
        map_.initialize(f.track_id, f.u_px, f.v_px, remap_of_[static_cast<std::size_t>(j)]);
    if (slot < 0) {
      record(f, lf::UpdateStatus::kNoSlot, -1);
      continue;
    }
    --budget;
    record(f, lf::UpdateStatus::kInitialized, slot);
  }
}

}  // namespace cleanslam::slam_core
