// SlamEstimator after the wheel-drop switch reports the robot set down (robot.on_set_down).
#include <numbers>

#include "cleanslam/firmware/slam_estimator.hpp"
#include "cleanslam/slam_core/dead_reckoner.hpp"

namespace cleanslam::firmware {

void SlamEstimator::set_down(hal::TimeNs t_ns) {
  if (config_.robot.on_set_down == RobotSettings::SetDown::kNewMap) {
    reset(t_ns);
    relocalizing_ = false;
    return;
  }
  // Relocalize: the map stays; the carry is an unknown planar displacement with zero mean,
  // folded in as a prediction (eq. 7) whose body noise is (x, y, yaw) only.
  predict(t_ns, true);
  const double s_xy = config_.robot.relocalize_std_m;
  const double s_yaw = config_.robot.relocalize_std_yaw_deg * std::numbers::pi / 180.0;
  slam_core::Matrix6d body_cov = slam_core::Matrix6d::Zero();
  body_cov(0, 0) = s_xy * s_xy;
  body_cov(1, 1) = s_xy * s_xy;
  body_cov(5, 5) = s_yaw * s_yaw;
  slam_core::Matrix6d J;
  (void)slam_core::camera_increment_from_body(slam_core::Vector6d::Zero(), ekf_.camera().R_body_c(),
                                              ekf_.camera().t_body_c(), &J);
  slam_core::OdometryIncrement carry;
  carry.Q = J * body_cov * J.transpose();
  (void)ekf_.predict(carry);
  relocalizing_ = true;
  updates_at_set_down_ = ekf_.counters().updates_applied;
}

bool SlamEstimator::pose_lost() const {
  return relocalizing_ && ekf_.counters().updates_applied == updates_at_set_down_;
}

}  // namespace cleanslam::firmware
