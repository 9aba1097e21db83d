#include "cleanslam/firmware/slam_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>

#include <Eigen/Eigenvalues>

#include "cleanslam/firmware/program.hpp"
#include "cleanslam/slam_core/camera_model.hpp"
#include "cleanslam/slam_core/geometry.hpp"

namespace cleanslam::firmware {

namespace lf = hal::log;

namespace {

lf::UpdateStatus record_status(slam_core::ObservationResult r) {
  switch (r) {
    case slam_core::ObservationResult::kFused:
      return lf::UpdateStatus::kUpdated;
    case slam_core::ObservationResult::kGate:
      return lf::UpdateStatus::kGated;
    case slam_core::ObservationResult::kDepthBound:
      return lf::UpdateStatus::kDepthBound;
    case slam_core::ObservationResult::kBehindCamera:
      return lf::UpdateStatus::kBehindCamera;
    default:
      return lf::UpdateStatus::kRejected;
  }
}

slam_core::SlamConfig slam_config(const FirmwareConfig& c) {
  slam_core::SlamConfig s = c.slam;
  slam_core::derive_dependent_settings(s);
  return s;
}

slam_core::EkfConfig ekf_config(const FirmwareConfig& c) {
  slam_core::EkfConfig e = slam_config(c).filter;
  if (c.gyro_errors_from_calibration) {
    e.gyro_bias_walk = std::max(e.gyro_bias_walk, c.calibration.gyro.bias_walk);
  }
  return e;
}

slam_core::DeadReckoningConfig dead_reckoning_config(const FirmwareConfig& c) {
  slam_core::DeadReckoningConfig d = slam_config(c).odometry;
  d.gyro_timeout_s = hal::to_seconds(c.loop.gyro_timeout_ns);
  if (c.gyro_errors_from_calibration) {
    d.gyro_scale_error = std::max(d.gyro_scale_error, c.calibration.gyro.scale_error);
  }
  return d;
}

// Frames of tracked features: the front end's data association with their own inlier minimum.
slam_core::frontend::JcbbConfig jcbb_config(const FirmwareConfig& c) {
  slam_core::frontend::JcbbConfig j = c.slam.frontend.jcbb;
  j.min_inliers = c.slam.map.features_min_inliers;
  return j;
}

slam_core::frontend::FramePipelineConfig pipeline_config(const FirmwareConfig& c) {
  slam_core::frontend::FramePipelineConfig p = c.slam.frontend;
  p.width = c.calibration.camera.width;
  p.height = c.calibration.camera.height;
  return p;
}

}  // namespace

std::unique_ptr<Estimator> make_estimator(const FirmwareConfig& config) {
  return std::make_unique<SlamEstimator>(config);
}

SlamEstimator::SlamEstimator(const FirmwareConfig& config)
    : config_(config),
      dr_(config.calibration, dead_reckoning_config(config)),
      ekf_(config.calibration, ekf_config(config)),
      jcbb_(jcbb_config(config)),
      pipeline_(std::make_unique<slam_core::frontend::FramePipeline>(pipeline_config(config))),
      adapter_(ekf_),
      camera_offset_ns_(hal::from_seconds(config.calibration.camera.time_offset_s)) {
  slot_owner_.fill(-1);
  merge_target_.fill(-1);
  ekf_.set_update_step(static_cast<std::int64_t>(config.loop.frame_work_budget) *
                       kUpdateWorkPerUnit);
  share_wheel_state();
}

void SlamEstimator::share_wheel_state() {
  slam_core::WheelYawFusion::StateEstimates e;
  e.bias = ekf_.gyro_bias();
  e.bias_var = ekf_.gyro_bias_variance();
  e.drift = ekf_.wheel_drift();
  e.drift_var = ekf_.wheel_drift_variance();
  dr_.set_wheel_state(e);
}

void SlamEstimator::reset(hal::TimeNs /*t_ns*/) {
  dr_ = slam_core::DeadReckoner(config_.calibration, dead_reckoning_config(config_));
  // The world frame is the body frame at the start: the camera pose follows from T_body_cam.
  const slam_core::Vector6d cam =
      slam_core::camera_pose_from_body_pose(slam_core::Vector6d::Zero(), ekf_.camera());
  // Always taken: the configuration's camera mount is checked (hal::camera_mount_error) to lie
  // within 10 m of the body's origin, far inside the filter's range.
  static_cast<void>(ekf_.reset(cam, slam_core::Matrix6d::Identity() * 1e-10));
  share_wheel_state();
  slot_owner_.fill(-1);
  merge_target_.fill(-1);
  pipeline_->forget_map();
  predicted_to_ns_ = -1;
  frame_done_ = true;
  fusing_ = false;
  record_count_ = 0;
}

void SlamEstimator::add_gyro(const hal::GyroSample& s) {
  dr_.add_gyro(s);
}

void SlamEstimator::add_encoder(const hal::EncoderSample& s) {
  dr_.add_encoder(s);
}

void SlamEstimator::predict(hal::TimeNs t_ns, bool /*gyro_ok: the dead reckoner sees it too*/) {
  // Deferred while an update is pending: the dead reckoner keeps the increment until it is done.
  if (t_ns > predicted_to_ns_ && !ekf_.update_pending()) {
    const slam_core::OdometryIncrement u = dr_.take_increment(t_ns);
    ekf_.predict(u);
    if (config_.slam.filter.wheel_drift_state) {
      // Every increment: fused window by window instead, the same information costs 0.27 m of
      // ATE on sparse seeds 1-40 (standard error 0.12 m).
      ekf_.fuse_wheel_gyro_mismatch(u.wheel_gyro_mismatch,
                                    config_.slam.odometry.wheel_yaw.gate_chi2);
      share_wheel_state();
      record_mismatch(t_ns);
    }
    predicted_to_ns_ = t_ns;
  }
}

void SlamEstimator::record_mismatch(hal::TimeNs t_ns) {
  const slam_core::MismatchStatus& m = ekf_.last_mismatch();
  fusion_record_count_ = std::min(m.count, static_cast<int>(fusion_records_.size()));
  for (int i = 0; i < fusion_record_count_; ++i) {
    const slam_core::ScalarFusionStatus& st = m.updates[static_cast<std::size_t>(i)];
    lf::FusionRecord& r = fusion_records_[static_cast<std::size_t>(i)];
    r.t_ns = t_ns;
    r.source = lf::FusionSource::kWheelGyroMismatch;
    r.index = static_cast<std::uint8_t>(i);
    r.fused = st.fused;
    r.innovation = st.innovation;
    r.innovation_variance = st.innovation_variance;
    r.test_ratio = st.test_ratio;
  }
}

int SlamEstimator::take_fusion_records(const hal::log::FusionRecord*& records) {
  records = fusion_records_.data();
  const int n = fusion_record_count_;
  fusion_record_count_ = 0;
  return n;
}

void SlamEstimator::begin_frame(const hal::CameraFrame& frame) {
  ekf_.finish_update();  // only when the loop abandoned a frame mid-update (lifted)
  fusing_ = false;
  frame_ = frame;
  frame_done_ = false;
  record_count_ = 0;
  image_mode_ = !frame.has_features() && frame.has_image();
  if (image_mode_) {
    ++image_frames_;
    predict(frame.t_ns + camera_offset_ns_, true);
    pipeline_->begin_frame(frame.image, !dr_.standing_still());
  }
}

bool SlamEstimator::step_frame(int& budget) {
  if (frame_done_) {
    return true;
  }
  if (image_mode_) {
    budget = 0;  // one bounded pipeline step per loop iteration
    if (pipeline_->step(adapter_)) {
      return false;
    }
    collect_image_records();
    frame_done_ = true;
    return true;
  }
  // The features path: association, JCBB and the start of one batch update; the update's rest in
  // bounded steps (one per loop iteration); then the records and the initializations.
  if (!fusing_) {
    budget -= frame_.feature_count;
    if (!frame_.has_features()) {
      frame_done_ = true;
      return true;
    }
    // Usually a no-op: the loop predicted up to the newest encoder sample, at or after the frame.
    predict(frame_.t_ns + camera_offset_ns_, true);
    if (!associate_features()) {
      frame_done_ = true;
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
  merge_remapped();
  initialize_features();
  frame_done_ = true;
  return true;
}

int SlamEstimator::slot_of(std::int64_t track_id) const {
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    if (slot_owner_[static_cast<std::size_t>(s)] == track_id && ekf_.slot_used(s)) {
      return s;
    }
  }
  return -1;
}

void SlamEstimator::record(const hal::FeatureObservation& f, lf::UpdateStatus status, int slot) {
  if (record_count_ >= static_cast<int>(records_.size())) {
    return;
  }
  lf::UpdateRecord& r = records_[static_cast<std::size_t>(record_count_++)];
  r = lf::UpdateRecord{};
  r.t_ns = frame_.t_ns;
  r.track_id = f.track_id;
  r.slot = slot;
  r.status = status;
  r.u_px = f.u_px;
  r.v_px = f.v_px;
}

bool SlamEstimator::associate_features() {
  const int n = frame_.feature_count;
  if (dr_.standing_still()) {
    for (int i = 0; i < n; ++i) {
      record(frame_.features[i], lf::UpdateStatus::kSkipped, slot_of(frame_.features[i].track_id));
    }
    return false;
  }
  const double w = config_.calibration.camera.width;
  const double h = config_.calibration.camera.height;
  // Enough mapped landmarks in view constrain the whole pose at once: no remapping then.
  int mapped = 0;
  for (int i = 0; i < n; ++i) {
    feature_slot_[static_cast<std::size_t>(i)] = slot_of(frame_.features[i].track_id);
    mapped += feature_slot_[static_cast<std::size_t>(i)] >= 0 ? 1 : 0;
  }
  remap_allowed_ = mapped <= config_.slam.map.remap_max_mapped_in_view;
  int m = 0;
  int fresh = 0;
  for (int i = 0; i < n; ++i) {
    const hal::FeatureObservation& f = frame_.features[i];
    if (!(f.u_px >= -0.5 && f.u_px < w - 0.5 && f.v_px >= -0.5 && f.v_px < h - 0.5)) {
      record(f, lf::UpdateStatus::kRejected, -1);
      continue;
    }
    const int slot = feature_slot_[static_cast<std::size_t>(i)];
    if (slot < 0 || needs_remap(slot)) {
      remap_of_[static_cast<std::size_t>(fresh)] = slot;
      new_feature_[static_cast<std::size_t>(fresh++)] = i;
      continue;
    }
    slam_core::PixelPrediction pp;
    if (m < kMaxObs && config_.slam.map.reinit_behind_camera &&
        !(ekf_.predict_pixel(slot, pp) && pp.in_front)) {
      // Seen, so in front: the landmark's estimate is wrong, a new one starts from this ray.
      ekf_.delete_landmark(slot);
      slot_owner_[static_cast<std::size_t>(slot)] = -1;
      remap_of_[static_cast<std::size_t>(fresh)] = -1;
      new_feature_[static_cast<std::size_t>(fresh++)] = i;
      continue;
    }
    if (m >= kMaxObs || !ekf_.predict_pixel(slot, pp) || !pp.in_front) {
      record(f,
             m < kMaxObs && !pp.in_front ? lf::UpdateStatus::kBehindCamera
                                         : lf::UpdateStatus::kRejected,
             slot);
      continue;
    }
    obs_[static_cast<std::size_t>(m)] = slam_core::Observation{slot, f.u_px, f.v_px};
    obs_feature_[static_cast<std::size_t>(m)] = i;
    ++m;
  }
  obs_count_ = m;
  fresh_count_ = fresh;
  innovation_count_ = -1;
  jcbb_result_ = slam_core::frontend::JcbbResult{};
  updated_ = false;
  if (m == 0) {
    return true;
  }
  innovation_count_ = ekf_.joint_pixel_innovation(
      std::span<const slam_core::Observation>(obs_.data(), static_cast<std::size_t>(m)), nu_, S_);
  if (innovation_count_ == m) {
    jcbb_result_ = jcbb_.solve(nu_.data(), S_.data(), m, inlier_.data());
  }
  int q = 0;
  if (jcbb_result_.update) {
    for (int i = 0; i < m; ++i) {
      if (inlier_[static_cast<std::size_t>(i)]) {
        inlier_obs_[static_cast<std::size_t>(q)] = obs_[static_cast<std::size_t>(i)];
        inlier_feature_[static_cast<std::size_t>(q)] = i;
        ++q;
      }
    }
  }
  if (q > 0) {
    ekf_.update(inlier_obs_.data(), q);
    updated_ = true;
  }
  return true;
}

void SlamEstimator::record_features_update() {
  const int m = obs_count_;
  const int k = innovation_count_;
  const bool jcbb_update = jcbb_result_.update;
  const slam_core::UpdateStatus* status = updated_ ? &ekf_.last_update() : nullptr;
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
      const auto ld = static_cast<std::size_t>(2 * m);
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

// Undelayed initialization of unseen ids, keeping at most kMaxObs landmarks in view.
void SlamEstimator::initialize_features() {
  int budget = kMaxObs - obs_count_;
  for (int j = 0; j < fresh_count_; ++j) {
    const hal::FeatureObservation& f = frame_.features[new_feature_[static_cast<std::size_t>(j)]];
    if (budget <= 0) {
      record(f, lf::UpdateStatus::kSkipped, -1);
      continue;
    }
    const int slot = ekf_.initialize_landmark(f.u_px, f.v_px);
    if (slot < 0) {
      record(f, lf::UpdateStatus::kNoSlot, -1);
      continue;
    }
    --budget;
    slot_owner_[static_cast<std::size_t>(slot)] = f.track_id;
    // The slot may be a recycled one (a full pool): no merge may refer to what it held.
    merge_target_[static_cast<std::size_t>(slot)] = -1;
    std::replace(merge_target_.begin(), merge_target_.end(), slot, -1);
    const int earlier = remap_of_[static_cast<std::size_t>(j)];
    if (earlier >= 0 && earlier != slot && ekf_.slot_used(earlier)) {
      slot_owner_[static_cast<std::size_t>(earlier)] = -1;
      merge_target_[static_cast<std::size_t>(slot)] = earlier;
    }
    record(f, lf::UpdateStatus::kInitialized, slot);
  }
}

bool SlamEstimator::needs_remap(int slot) const {
  const double limit = config_.slam.map.remap_pixel_std_px;
  if (!(limit > 0.0) || !remap_allowed_ || merge_target_[static_cast<std::size_t>(slot)] >= 0) {
    return false;
  }
  // Only with the heading lost: with a known pose a poor prediction is the landmark's own doing.
  if (!(std::sqrt(std::max(0.0, ekf_.pose_covariance()(5, 5))) >
        config_.slam.map.remap_min_yaw_std_deg * std::numbers::pi / 180.0)) {
    return false;
  }
  slam_core::PixelPrediction pp;
  if (!ekf_.predict_pixel(slot, pp) || !pp.in_front) {
    return true;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(pp.S, Eigen::EigenvaluesOnly);
  return !(std::sqrt(std::max(0.0, eig.eigenvalues()(1))) <= limit);
}

// A remapped landmark joins its earlier entry once its depth relative to the camera has converged
// (the young test's fraction) or its track was not in this frame.
void SlamEstimator::merge_remapped() {
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
    bool seen = false;
    for (int i = 0; i < obs_count_; ++i) {
      seen = seen || obs_[static_cast<std::size_t>(i)].slot == s;
    }
    const double rel = ekf_.relative_depth_std(s);
    if (seen && !(rel >= 0.0 && rel < config_.slam.filter.young_depth_std_fraction)) {
      continue;
    }
    const std::int64_t track = slot_owner_[ss];
    merge_target_[ss] = -1;
    const hal::FeatureObservation f{track, 0.0, 0.0};
    const int records_before = record_count_;
    if (ekf_.merge_landmarks(earlier, s, config_.slam.map.remap_merge_gate_chi2) ==
        slam_core::ObservationResult::kFused) {
      slot_owner_[static_cast<std::size_t>(earlier)] = track;
      slot_owner_[ss] = -1;
      record(f, lf::UpdateStatus::kMerged, earlier);
    } else {
      ekf_.delete_landmark(earlier);
      record(f, lf::UpdateStatus::kMergeGated, s);
    }
    if (record_count_ > records_before && ekf_.last_merge_test_ratio() >= 0.0) {
      records_[static_cast<std::size_t>(records_before)].mahalanobis2 =
          ekf_.last_merge_test_ratio();
    }
  }
}

// Image path: one record per searched landmark (track id = slot) and per new landmark.
void SlamEstimator::collect_image_records() {
  const auto& report = pipeline_->report();
  for (int i = 0; i < pipeline_->track_count(); ++i) {
    const slam_core::frontend::TrackRecord& t = pipeline_->tracks()[i];
    lf::UpdateStatus st = lf::UpdateStatus::kRejected;  // not found by the tracker
    if (t.result.found) {
      st = !t.inlier        ? lf::UpdateStatus::kGated
           : report.updated ? lf::UpdateStatus::kUpdated
                            : lf::UpdateStatus::kSkipped;
    }
    record(hal::FeatureObservation{t.slot, t.result.u_px, t.result.v_px}, st, t.slot);
  }
  for (int i = 0; i < pipeline_->new_landmark_count(); ++i) {
    const auto& o = pipeline_->new_landmark(i);
    record(hal::FeatureObservation{o.slot, o.u_px, o.v_px}, lf::UpdateStatus::kInitialized, o.slot);
  }
}

int SlamEstimator::update_records(const lf::UpdateRecord*& records) const {
  records = records_.data();
  return record_count_;
}

hal::PoseEstimate SlamEstimator::pose(hal::TimeNs t_ns) const {
  return ekf_.body_pose_estimate(t_ns);
}

bool SlamEstimator::standing_still() const {
  return dr_.standing_still();
}

hal::PoseEstimate SlamEstimator::dead_reckoning_pose(hal::TimeNs t_ns) const {
  hal::PoseEstimate p;
  p.t_ns = t_ns;
  p.position_m = {dr_.x(), dr_.y(), 0.0};
  const double yaw = dr_.yaw();
  p.orientation_wxyz = {std::cos(yaw / 2.0), 0.0, 0.0, std::sin(yaw / 2.0)};
  return p;
}

MapCounters SlamEstimator::map_counters() const {
  const slam_core::EkfCounters& c = ekf_.counters();
  MapCounters m;
  m.initialized = c.landmarks_initialized;
  m.replaced = c.landmarks_replaced;
  m.deleted = c.landmarks_deleted;
  m.merged = c.landmarks_merged;
  m.merges_gated = c.merges_gated;
  return m;
}

ObservationRejections SlamEstimator::observation_rejections() const {
  static_assert(slam_core::kObservationResultCount <= kMaxRejectionReasons);
  const slam_core::RejectionCounters& c = ekf_.counters().rejections;
  ObservationRejections out;
  for (int i = 0; i < slam_core::kObservationResultCount; ++i) {
    const auto r = static_cast<slam_core::ObservationResult>(i);
    if (r != slam_core::ObservationResult::kFused && c[r] > 0) {
      out.by_reason[static_cast<std::size_t>(out.count++)] = {slam_core::to_string(r), c[r]};
    }
  }
  return out;
}

bool SlamEstimator::wheel_yaw(WheelYawReport& out) const {
  if (!config_.slam.odometry.wheel_yaw.enabled) {
    return false;
  }
  const slam_core::WheelYawFusion& f = dr_.wheel_yaw_fusion();
  const Eigen::Vector3d& p = f.calibration();
  const Eigen::Matrix3d& P = f.calibration_covariance();
  out.gyro_bias_rad_s = p(0);
  out.scale = p(1);
  out.scale_std = std::sqrt(std::max(0.0, P(1, 1)));
  out.drift_rad_per_m = p(2);
  out.drift_std = std::sqrt(std::max(0.0, P(2, 2)));
  const slam_core::WheelYawCounters& k = f.counters();
  out.intervals_fused = k.intervals_fused;
  out.intervals_gated = k.intervals_gated;
  out.windows_used = k.windows_used;
  out.windows_gated = k.windows_gated;
  out.drift_state = config_.slam.filter.wheel_drift_state;
  if (out.drift_state) {
    out.state_drift_rad_per_m = ekf_.wheel_drift();
    out.state_drift_std = std::sqrt(std::max(0.0, ekf_.wheel_drift_variance()));
    out.state_gyro_bias_rad_s = ekf_.gyro_bias();
    out.state_gyro_bias_std = std::sqrt(std::max(0.0, ekf_.gyro_bias_variance()));
    out.mismatches_fused = ekf_.counters().wheel_gyro_mismatches_fused;
    out.mismatches_gated = ekf_.counters().wheel_gyro_mismatches_gated;
  }
  return true;
}

int SlamEstimator::landmarks(LandmarkEstimate* out, int max) const {
  int n = 0;
  for (int s = 0; s < hal::kMaxLandmarks && n < max; ++s) {
    if (!ekf_.slot_used(s)) {
      continue;
    }
    LandmarkEstimate& l = out[n++];
    l.slot = s;
    const Eigen::Vector3d p = ekf_.landmark(s);
    const Eigen::Matrix3d c = ekf_.landmark_covariance(s);
    l.position_m = {p.x(), p.y(), p.z()};
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) {
        l.covariance[static_cast<std::size_t>(3 * r + k)] = c(r, k);
      }
    }
  }
  return n;
}

}  // namespace cleanslam::firmware
