#pragma once

#include <array>

#include <Eigen/Core>

#include "cleanslam/slam_core/camera_frame_measurement.hpp"
#include "cleanslam/slam_core/ekf.hpp"

// A pose lost among established landmarks: four landmarks mapped at known depths (2-3 m) from a
// certain pose, the pose's planar covariance then inflated by a motion of unknown length and turn,
// and the sightings of the landmarks from the true pose, `offset` (x, y, yaw) from the estimate.
namespace cleanslam::test {

struct PoseSolveScenario {
  std::array<slam_core::Observation, 4> obs{};
  slam_core::Vector6d truth = slam_core::Vector6d::Zero();
  int count = 0;
};

inline PoseSolveScenario make_pose_solve_scenario(slam_core::Ekf& ekf, double planar_std_m,
                                                  double yaw_std_rad,
                                                  const Eigen::Vector3d& offset) {
  namespace cs = slam_core;
  PoseSolveScenario sc;
  cs::Matrix6d P0 = cs::Matrix6d::Identity() * 1e-8;
  (void)ekf.reset(cs::Vector6d::Zero(), P0);
  const std::array<std::array<double, 3>, 4> px = {
      {{60.0, 80.0, 2.0}, {250.0, 90.0, 2.5}, {120.0, 170.0, 2.2}, {200.0, 150.0, 3.0}}};
  std::array<int, 4> slots{};
  for (std::size_t i = 0; i < px.size(); ++i) {
    slots[i] = ekf.initialize_landmark(px[i][0], px[i][1], px[i][2], 1e-3);
  }
  cs::OdometryIncrement u;
  u.Q.diagonal() << planar_std_m * planar_std_m, planar_std_m * planar_std_m, 1e-10, 1e-10, 1e-10,
      yaw_std_rad * yaw_std_rad;
  u.dt_s = 1.0;
  (void)ekf.predict(u);
  sc.truth = ekf.camera_pose();
  sc.truth(0) += offset(0);
  sc.truth(1) += offset(1);
  sc.truth(5) += offset(2);
  for (std::size_t i = 0; i < px.size(); ++i) {
    Eigen::Vector2d uv;
    if (slots[i] >= 0 &&
        ekf.camera().project(cs::predict_camera_point(sc.truth, ekf.landmark(slots[i])), uv,
                             nullptr)) {
      sc.obs[static_cast<std::size_t>(sc.count++)] = {slots[i], uv.x(), uv.y()};
    }
  }
  return sc;
}

}  // namespace cleanslam::test
