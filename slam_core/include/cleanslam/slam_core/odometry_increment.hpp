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
  // The gyro's turn less the wheels' in each fused encoder interval, with the dead reckoner's
  // bias and the wheels' heading scale applied: z = b dt - c d + noise of variance r, i.e.
  // z = h^T (b, c) with h = (dt, -d). Kept as the information the intervals hold about (b, c),
  // sum h h^T / r and sum h z / r: a window of them is worth the intervals one by one. With
  // inverse-variance weights the fused turn and z are independent, so the filter may use both.
  struct WheelGyroMismatch {
    Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
    Eigen::Vector2d information_vector = Eigen::Vector2d::Zero();
    int intervals = 0;
    void add(double z, double dt, double distance, double variance) {
      if (!(variance > 0.0)) {
        return;
      }
      const Eigen::Vector2d h(dt, -distance);
      information += h * h.transpose() / variance;
      information_vector += h * (z / variance);
      ++intervals;
    }
  } wheel_gyro_mismatch;
  double distance_m = 0.0;  // travelled by the body (unsigned)
  double dt_s = 0.0;
  bool gyro_used = true;  // false when the heading came from the encoders alone
};

}  // namespace cleanslam::slam_core
