#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "cleanslam/slam_core/ekf.hpp"

// Ekf::relocate: the pose estimate moves, its covariance and the map stay.
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

TEST(EkfRelocate, MovesThePoseAndKeepsTheCovarianceAndTheMap) {
  const hal::Calibration calibration;
  cs::Ekf ekf(calibration, cs::EkfConfig{});
  cs::Matrix6d P0 = cs::Matrix6d::Identity() * 1e-3;
  P0(5, 5) = 0.1;
  ASSERT_TRUE(ekf.reset(cs::Vector6d::Zero(), P0));
  const int slot = ekf.initialize_landmark(100.0, 90.0);
  ASSERT_GE(slot, 0);
  const Eigen::MatrixXd P = ekf.covariance();
  const Eigen::Vector3d landmark = ekf.landmark(slot);
  cs::Vector6d pose;
  pose << 1.0, -2.0, 0.1, 0.0, -0.1, 4.0;
  ASSERT_TRUE(ekf.relocate(pose));
  EXPECT_EQ(ekf.camera_pose().head<5>(), pose.head<5>());
  EXPECT_NEAR(ekf.camera_pose()(5), 4.0 - 2.0 * M_PI, 1e-12);  // wrapped
  EXPECT_EQ(ekf.covariance(), P);
  EXPECT_EQ(ekf.landmark(slot), landmark);
  pose(0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(ekf.relocate(pose));
  EXPECT_EQ(ekf.camera_pose()(0), 1.0);
}
