#include "cleanslam/slam_core/slam_system.hpp"

#include <algorithm>
#include <cmath>

#include "cleanslam/slam_core/geometry.hpp"

namespace cleanslam::slam_core {

namespace lf = hal::log;

namespace {

// The front end works on the calibrated image size.
SlamConfig resolved(const hal::Calibration& calibration, SlamConfig c) {
  c.frontend.width = calibration.camera.width;
  c.frontend.height = calibration.camera.height;
  return c;
}

}  // namespace

SlamSystem::SlamSystem(const hal::Calibration& calibration, const SlamConfig& config)
    : calibration_(calibration),
      config_(resolved(calibration, config)),
      dr_(calibration, config_.odometry),
      ekf_(calibration, config_.filter),
      map_(ekf_, config_.map),
      jcbb_(frontend::JcbbConfig{.min_inliers = config_.map.features_min_inliers}),
      pipeline_(std::make_unique<frontend::FramePipeline>(config_.frontend)),
      mapped_(ekf_, map_),
      camera_offset_ns_(hal::from_seconds(calibration.camera.time_offset_s)),
      relocalizer_(ekf_.camera(), config_.relocalizer) {
  ekf_.set_update_step(config_.update_work_step);
}

void SlamSystem::reset() {
  dr_ = DeadReckoner(calibration_, config_.odometry);
  // The world frame is the body frame at the start: the camera pose follows from T_body_cam.
  const Vector6d cam = camera_pose_from_body_pose(Vector6d::Zero(), ekf_.camera());
  // Always taken: the configuration's camera mount is checked (hal::camera_mount_error) to lie
  // within 10 m of the body's origin, far inside the filter's range.
  static_cast<void>(ekf_.reset(cam, Matrix6d::Identity() * 1e-10));
  map_.forget();
  pipeline_->forget_map();
  predicted_to_ns_ = -1;
  frame_done_ = true;
  fusing_ = false;
  record_count_ = 0;
  relocalizing_ = false;
  position_std_exceeded_ = false;
}

void SlamSystem::predict(hal::TimeNs t_ns) {
  if (t_ns <= predicted_to_ns_ || ekf_.update_pending()) {
    return;
  }
  const OdometryIncrement u = dr_.take_increment(t_ns);
  ekf_.predict(u);
  predicted_to_ns_ = t_ns;
  check_position_std();
}

void SlamSystem::begin_frame(const hal::CameraFrame& frame) {
  ekf_.finish_update();  // only when the caller abandoned a frame mid-update (lifted)
  fusing_ = false;
  frame_ = frame;
  frame_done_ = false;
  record_count_ = 0;
  relocalizer_started_ = false;
  image_mode_ = !frame.has_features() && frame.has_image();
  if (image_mode_) {
    ++image_frames_;
    predict(frame.t_ns + camera_offset_ns_);
    pipeline_->begin_frame(frame.image, !dr_.standing_still());
  }
}

bool SlamSystem::step_frame(int& budget) {
  if (frame_done_) {
    return true;
  }
  if (!image_mode_) {
    frame_done_ = step_features(budget);
    if (frame_done_) {
      check_position_std();
    }
    return frame_done_;
  }
  budget = 0;  // one bounded pipeline step per call
  if (pipeline_->step(mapped_)) {
    return false;
  }
  if (map_.dormant_count() > 0 && !relocalize_step()) {
    return false;
  }
  collect_image_records();
  check_position_std();
  frame_done_ = true;
  return true;
}

void SlamSystem::record(const hal::FeatureObservation& f, lf::UpdateStatus status, int slot) {
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

void SlamSystem::check_position_std() {
  const hal::PoseEstimate p = ekf_.body_pose_estimate(0);
  const double var = std::max(p.covariance[0], p.covariance[7]);
  const double limit = config_.map.pose_lost_position_std_m;
  const double found = kPoseFoundStdFraction * limit;
  if (var > limit * limit) {
    position_std_exceeded_ = true;
  } else if (var < found * found) {
    position_std_exceeded_ = false;
  }
}

hal::PoseEstimate SlamSystem::dead_reckoning_pose(hal::TimeNs t_ns) const {
  hal::PoseEstimate p;
  p.t_ns = t_ns;
  p.position_m = {dr_.x(), dr_.y(), 0.0};
  const double yaw = dr_.yaw();
  p.orientation_wxyz = {std::cos(yaw / 2.0), 0.0, 0.0, std::sin(yaw / 2.0)};
  return p;
}

}  // namespace cleanslam::slam_core
