#pragma once

#include <Eigen/Core>

namespace cleanslam::slam_core {

// u of eq. 9: the increment of the camera pose between two camera frames, expressed in the
// camera frame at the first of them, with its covariance Q over (dx_c, dpsi_c).
struct OdometryIncrement {
  Eigen::Vector3d dx_c = Eigen::Vector3d::Zero();
  Eigen::Vector3d dpsi_c = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 6, 6> Q = Eigen::Matrix<double, 6, 6>::Zero();
  double distance_m = 0.0;  // travelled by the body (unsigned)
  double dt_s = 0.0;
  bool gyro_used = true;  // false when the heading came from the encoders alone
};

}  // namespace cleanslam::slam_core
