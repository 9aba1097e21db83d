// SlamSystem after a set-down (MapConfig::on_set_down).
#include <numbers>

#include "cleanslam/slam_core/slam_system.hpp"

namespace cleanslam::slam_core {

void SlamSystem::set_down(hal::TimeNs t_ns) {
  if (config_.map.on_set_down == MapConfig::SetDown::kNewMap) {
    reset();
    return;
  }
  // Relocalize: the map stays; the carry is an unknown planar displacement with zero mean,
  // folded in as a prediction (eq. 7) whose body noise is (x, y, yaw) only.
  predict(t_ns);
  const Eigen::Vector3d v = set_down_variances();
  Matrix6d body_cov = Matrix6d::Zero();
  body_cov(0, 0) = v(0);
  body_cov(1, 1) = v(1);
  body_cov(5, 5) = v(2);
  Matrix6d J;
  (void)camera_increment_from_body(Vector6d::Zero(), ekf_.camera().R_body_c(),
                                   ekf_.camera().t_body_c(), &J);
  OdometryIncrement carry;
  carry.Q = J * body_cov * J.transpose();
  (void)ekf_.predict(carry);
  if (image_mode_) {
    // Where the map is, is not known: its landmarks wait, unsearched, for the Relocalizer.
    map_.set_dormant();
    pipeline_->suspend_map();
  }
  relocalizing_ = true;
  updates_at_set_down_ = ekf_.counters().updates_applied;
}

Eigen::Vector3d SlamSystem::set_down_variances() const {
  const double s_xy = config_.map.relocalize_std_m;
  const double s_yaw = config_.map.relocalize_std_yaw_deg * std::numbers::pi / 180.0;
  return {s_xy * s_xy, s_xy * s_xy, s_yaw * s_yaw};
}

bool SlamSystem::relocalize_step() {
  const frontend::FrameReport& report = pipeline_->report();
  if (!relocalizer_started_) {
    if (report.image_check != frontend::ImageCheck::kOk || report.featureless) {
      return true;
    }
    relocalizer_.begin(frame_.image, pipeline_->detector().corners(),
                       pipeline_->detector().corner_count(), ekf_.camera_pose());
    relocalizer_started_ = true;
    relocalizer_cursor_ = 0;
    return false;
  }
  if (relocalizer_cursor_ < hal::kMaxLandmarks) {
    int added = 0;
    for (;
         relocalizer_cursor_ < hal::kMaxLandmarks && added < config_.relocalizer.landmarks_per_step;
         ++relocalizer_cursor_) {
      const int s = relocalizer_cursor_;
      const frontend::LandmarkPatch* patch = pipeline_->patches().get(s);
      if (map_.dormant(s) && patch != nullptr) {
        relocalizer_.add_landmark(s, ekf_.landmark(s), *patch);
        ++added;
      }
    }
    return false;
  }
  if (!relocalizer_.search_step()) {
    return false;
  }
  Vector6d pose;
  if (relocalizer_.found(pose)) {
    relocate(pose);
  }
  return true;
}

// The pose found: the landmarks mapped since the set-down (made from the wrong pose) go, the
// dormant ones are searched again. What the filter learnt of x, y and yaw since the set-down came
// from those landmarks, in the wrong frame: the pose found is taken as uncertain as a set-down.
void SlamSystem::relocate(const Vector6d& camera_pose) {
  const Eigen::Matrix3d planar_cov = set_down_variances().asDiagonal();
  if (!ekf_.relocate(camera_pose, planar_cov)) {
    return;
  }
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    if (ekf_.slot_used(s) && !map_.dormant(s)) {
      mapped_.delete_landmark(s);
      pipeline_->forget(s);
    }
  }
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    if (map_.dormant(s)) {
      pipeline_->resume(s);
    }
  }
  map_.wake();
  ++relocalizations_;
}

bool SlamSystem::pose_lost() const {
  // Image frames: updates against landmarks made since the set-down do not find the map.
  return (relocalizing_ &&
          (map_.dormant_count() > 0 || ekf_.counters().updates_applied == updates_at_set_down_)) ||
         position_std_exceeded();
}

}  // namespace cleanslam::slam_core
