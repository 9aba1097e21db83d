#pragma once

#include <Eigen/Core>

namespace cleanslam::slam_core {

// u of eq. 9: the increment of the camera pose between two camera frames, expressed in the
// camera frame at the first of them, with its covariance Q over (dx_c, dpsi_c).
struct OdometryIncrement {
  Eigen::Vector3d dx_c = Eigen::Vector3d::Zero();
  Eigen::Vector3d dpsi_c = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 6, 6> Q = Eigen::Matrix<double, 6, 6>::Zero();
  // d (dx_c, dpsi_c) / d b: how the increment changes with a residual gyro bias b (rad/s) that
  // the dead reckoner did not subtract.
  Eigen::Matrix<double, 6, 1> du_dbias = Eigen::Matrix<double, 6, 1>::Zero();
  // d (dx_c, dpsi_c) / d s: how it changes with a distance scale error s of the wheels (the
  // travelled distance is the measured one times 1 + s).
  Eigen::Matrix<double, 6, 1> du_dscale = Eigen::Matrix<double, 6, 1>::Zero();
  // d (dx_c, dpsi_c) / d c: how it changes with the wheels' heading drift per metre c
  // (wheel_yaw_fusion.hpp) when the dead reckoner leaves c to the filter
  // (EkfConfig::wheel_drift_state): the fused heading counts the wheels' turn less c d.
  Eigen::Matrix<double, 6, 1> du_ddrift = Eigen::Matrix<double, 6, 1>::Zero();
  // The gyro's turn less the wheels' over the increment's fused encoder intervals, with the dead
  // reckoner's bias and the wheels' heading scale applied: z = b dt - c distance + noise of
  // variance `variance` (the gyro's and the wheels' noise). With inverse-variance weights the
  // fused turn and this difference are independent, so the filter may use both.
  struct WheelGyroMismatch {
    double z = 0.0;
    double dt = 0.0;
    double distance = 0.0;  // signed
    double variance = 0.0;
    int intervals = 0;
  } wheel_gyro_mismatch;
  double distance_m = 0.0;  // travelled by the body (unsigned)
  double dt_s = 0.0;
  bool gyro_used = true;  // false when the heading came from the encoders alone
};

}  // namespace cleanslam::slam_core
