#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "cleanslam/slam_core/ekf.hpp"

// Ekf::relocate: the pose estimate moves; x, y and yaw take the given covariance and lose their
// correlations (what the lost estimate knew of them is void); the rest of the pose and the map
// stay.
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

TEST(EkfRelocate, MovesThePoseAndResetsItsPlanarCovarianceAndKeepsTheMap) {
  const hal::Calibration calibration;
  cs::Ekf ekf(calibration, cs::EkfConfig{});
  cs::Matrix6d P0 = cs::Matrix6d::Identity() * 1e-3;
  P0(5, 5) = 0.1;
  ASSERT_TRUE(ekf.reset(cs::Vector6d::Zero(), P0));
  const int slot = ekf.initialize_landmark(100.0, 90.0);
  ASSERT_GE(slot, 0);
  const Eigen::MatrixXd P = ekf.covariance();
  const int lm = 6 + 3 * slot;
  ASSERT_NE(P(0, lm), 0.0);  // the landmark was made from the pose: correlated
  const Eigen::Vector3d landmark = ekf.landmark(slot);
  cs::Vector6d pose;
  pose << 1.0, -2.0, 0.1, 0.0, -0.1, 4.0;
  Eigen::Matrix3d planar;
  planar << 0.09, 0.01, 0.0, 0.01, 0.04, 0.002, 0.0, 0.002, 0.12;
  ASSERT_TRUE(ekf.relocate(pose, planar));
  EXPECT_EQ(ekf.camera_pose().head<5>(), pose.head<5>());
  EXPECT_NEAR(ekf.camera_pose()(5), 4.0 - 2.0 * M_PI, 1e-12);  // wrapped
  const Eigen::MatrixXd Q = ekf.covariance();
  const int rows[3] = {0, 1, 5};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(Q(rows[i], rows[j]), planar(i, j)) << i << "," << j;
    }
  }
  for (const int r : rows) {
    for (const int c : {2, 3, 4, lm, lm + 1, lm + 2}) {
      EXPECT_EQ(Q(r, c), 0.0) << r << "," << c;
      EXPECT_EQ(Q(c, r), 0.0) << c << "," << r;
    }
  }
  for (const int r : {2, 3, 4, lm, lm + 1, lm + 2}) {
    for (const int c : {2, 3, 4, lm, lm + 1, lm + 2}) {
      EXPECT_EQ(Q(r, c), P(r, c)) << r << "," << c;
    }
  }
  EXPECT_EQ(ekf.landmark(slot), landmark);

  // Nothing changes for a pose or covariance that cannot be taken.
  const cs::Vector6d before = ekf.camera_pose();
  const Eigen::MatrixXd P1 = ekf.covariance();
  cs::Vector6d bad = pose;
  bad(0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(ekf.relocate(bad, planar));
  Eigen::Matrix3d not_pd = planar;
  not_pd(2, 2) = -0.1;
  EXPECT_FALSE(ekf.relocate(pose * 2.0, not_pd));
  not_pd = planar;
  not_pd(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(ekf.relocate(pose * 2.0, not_pd));
  EXPECT_EQ(ekf.camera_pose(), before);
  EXPECT_EQ(ekf.covariance(), P1);
}
