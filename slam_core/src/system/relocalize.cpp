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
  const double s_xy = config_.map.relocalize_std_m;
  const double s_yaw = config_.map.relocalize_std_yaw_deg * std::numbers::pi / 180.0;
  Matrix6d body_cov = Matrix6d::Zero();
  body_cov(0, 0) = s_xy * s_xy;
  body_cov(1, 1) = s_xy * s_xy;
  body_cov(5, 5) = s_yaw * s_yaw;
  Matrix6d J;
  (void)camera_increment_from_body(Vector6d::Zero(), ekf_.camera().R_body_c(),
                                   ekf_.camera().t_body_c(), &J);
  OdometryIncrement carry;
  carry.Q = J * body_cov * J.transpose();
  (void)ekf_.predict(carry);
  relocalizing_ = true;
  updates_at_set_down_ = ekf_.counters().updates_applied;
}

bool SlamSystem::pose_lost() const {
  return relocalizing_ && ekf_.counters().updates_applied == updates_at_set_down_;
}

}  // namespace cleanslam::slam_core
