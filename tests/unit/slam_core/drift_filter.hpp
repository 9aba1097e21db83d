#pragma once

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "cleanslam/slam_core/ekf.hpp"

// A filter with the gyro bias and wheel drift states (EkfConfig::wheel_drift_state), one landmark
// and two increments that correlate the pose, the bias and the drift with it.
namespace cleanslam::test {

inline constexpr double kDriftFilterBiasStd = 0.005;
inline constexpr double kDriftFilterDriftStd = 0.5;

inline slam_core::EkfConfig drift_config(bool invariant_reset) {
  slam_core::EkfConfig c;
  c.gyro_bias_state = true;
  c.gyro_bias_walk = 0.0005;
  c.wheel_drift_state = true;
  c.wheel_drift_std_rad_per_m = kDriftFilterDriftStd;
  c.invariant_reset = invariant_reset;
  return c;
}

inline hal::Calibration drift_calibration() {
  hal::Calibration cal;
  cal.gyro.bias_instability = kDriftFilterBiasStd;
  return cal;
}

inline void prepare_drift_filter(slam_core::Ekf& ekf) {
  slam_core::Vector6d pose;
  pose << 0.3, -0.2, 0.1, 0.0, 0.0, 0.4;
  ASSERT_TRUE(ekf.reset(pose, slam_core::Matrix6d::Identity() * 1e-4));
  ASSERT_GE(ekf.initialize_landmark(150.0, 110.0, 2.0, 0.3), 1);
  for (int k = 0; k < 2; ++k) {
    slam_core::OdometryIncrement u;
    u.dx_c = Eigen::Vector3d(0.0, 0.0, 0.1);
    u.dpsi_c = Eigen::Vector3d(0.0, -0.05, 0.0);
    u.Q.diagonal() << 1e-4, 1e-5, 1e-4, 1e-6, 1e-5, 1e-6;
    u.du_dbias << 0.0, 0.0, 0.0, 0.0, -0.5, 0.0;
    u.du_ddrift << 0.002, 0.0, 0.0, 0.0, 0.07, 0.0;
    u.dt_s = 0.5;
    ASSERT_TRUE(ekf.predict(u).applied());
  }
}

}  // namespace cleanslam::test
