#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "cleanslam/slam_core/ekf.hpp"
#include "symmetric_eigen.hpp"

// Ekf::merge_landmarks: the linear constraint y_keep - y_drop = 0 against a dense Kalman update.
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

// x_after, P_after equal x_ref, P_ref outside the dropped slot's rows and columns [d, d + 3).
void expect_equal_outside(const Eigen::VectorXd& x_after, const Eigen::MatrixXd& P_after,
                          const Eigen::VectorXd& x_ref, const Eigen::MatrixXd& P_ref, int d) {
  const auto n = static_cast<int>(x_ref.size());
  for (int i = 0; i < n; ++i) {
    if (i >= d && i < d + 3) {
      continue;
    }
    EXPECT_NEAR(x_after(i), x_ref(i), 1e-9 * (1.0 + std::abs(x_ref(i)))) << "row " << i;
    for (int j = 0; j < n; ++j) {
      if (j < d || j >= d + 3) {
        EXPECT_NEAR(P_after(i, j), P_ref(i, j), 1e-9 * (1.0 + std::abs(P_ref(i, j))))
            << i << "," << j;
      }
    }
  }
}

cs::EkfConfig merge_config(bool considers_kept) {
  cs::EkfConfig config;
  config.merge_considers_kept = considers_kept;
  config.invariant_reset = false;  // the dense references are the plain updates
  return config;
}

class EkfMergeTest : public ::testing::Test {
 protected:
  explicit EkfMergeTest(bool considers_kept = false)
      : ekf_(calibration_, merge_config(considers_kept)) {
    cs::Matrix6d P0 = cs::Matrix6d::Identity() * 1e-3;
    P0(5, 5) = 0.04;
    P0(0, 5) = P0(5, 0) = 0.002;
    cs::Vector6d pose = cs::Vector6d::Zero();
    pose << 0.3, -0.2, 0.1, 0.0, 0.0, 0.4;
    EXPECT_TRUE(ekf_.reset(pose, P0));
  }

  // Three landmarks: keep (depth known to 0.3 m), another, and drop, a second sighting of keep's
  // point at (drop_u, drop_v) with its depth unknown; the dense H, S of their merge.
  struct Scene {
    int keep = -1, other = -1, drop = -1, n = 0;
    Eigen::VectorXd x;
    Eigen::MatrixXd P, H, R, S;
  };
  Scene scene(double drop_u, double drop_v, double r) {
    Scene sc;
    sc.keep = ekf_.initialize_landmark(140.0, 110.0, 2.0, 0.3);
    sc.other = ekf_.initialize_landmark(250.0, 60.0);
    sc.drop = ekf_.initialize_landmark(drop_u, drop_v);
    sc.n = ekf_.active_dim();
    sc.x = ekf_.state().head(sc.n);
    sc.P = ekf_.covariance().topLeftCorner(sc.n, sc.n);
    sc.H = Eigen::MatrixXd::Zero(3, sc.n);
    if (sc.keep >= 0 && sc.drop >= 0) {
      sc.H.middleCols<3>(6 + 3 * sc.keep).setIdentity();
      sc.H.middleCols<3>(6 + 3 * sc.drop) = -Eigen::Matrix3d::Identity();
    }
    sc.R = r * r * Eigen::MatrixXd::Identity(3, 3);
    sc.S = sc.H * sc.P * sc.H.transpose() + sc.R;
    return sc;
  }

  hal::Calibration calibration_;
  cs::Ekf ekf_;
};

class EkfConsideredMergeTest : public EkfMergeTest {
 protected:
  EkfConsideredMergeTest() : EkfMergeTest(true) {}
};

TEST_F(EkfMergeTest, EqualsTheDenseKalmanUpdateAndFreesTheDroppedSlot) {
  const double r = 0.01;
  const Scene sc = scene(141.5, 109.0, r);
  const int keep = sc.keep;
  const int other = sc.other;
  const int drop = sc.drop;
  ASSERT_GE(keep, 0);
  ASSERT_GE(other, 0);
  ASSERT_GE(drop, 0);
  const int n = sc.n;
  const Eigen::VectorXd& x = sc.x;
  const Eigen::MatrixXd& P = sc.P;
  const Eigen::MatrixXd& H = sc.H;
  const Eigen::MatrixXd& S = sc.S;
  const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
  const Eigen::VectorXd x_ref = x + K * (-(H * x));
  const Eigen::MatrixXd P_ref = P - K * S * K.transpose();
  const Eigen::Vector3d nu = -(H * x);
  const double ratio = nu.dot(S.inverse() * nu);

  EXPECT_EQ(ekf_.last_merge_test_ratio(), -1.0);
  ASSERT_EQ(ekf_.merge_landmarks(keep, drop, 11.34, r), cs::ObservationResult::kFused);
  EXPECT_NEAR(ekf_.last_merge_test_ratio(), ratio, 1e-9 * ratio);
  EXPECT_GT(ratio, 0.0);
  EXPECT_FALSE(ekf_.slot_used(drop));
  EXPECT_TRUE(ekf_.slot_used(keep));
  EXPECT_TRUE(ekf_.slot_used(other));
  EXPECT_EQ(ekf_.landmark_count(), 2);
  EXPECT_EQ(ekf_.counters().landmarks_merged, 1U);
  const Eigen::VectorXd x_after = ekf_.state().head(n);
  const Eigen::MatrixXd P_after = ekf_.covariance().topLeftCorner(n, n);
  const int d = 6 + 3 * drop;
  for (int i = 0; i < n; ++i) {
    if (i >= d && i < d + 3) {
      EXPECT_EQ(x_after(i), 0.0);
      continue;
    }
    EXPECT_NEAR(x_after(i), x_ref(i), 1e-9 * (1.0 + std::abs(x_ref(i)))) << "row " << i;
    for (int j = 0; j < n; ++j) {
      if (j >= d && j < d + 3) {
        EXPECT_EQ(P_after(i, j), 0.0);
        continue;
      }
      EXPECT_NEAR(P_after(i, j), P_ref(i, j), 1e-9 * (1.0 + std::abs(P_ref(i, j))))
          << i << "," << j;
    }
  }
  EXPECT_EQ(cleanslam::test::asymmetry(P_after), 0.0);
  EXPECT_GE(cleanslam::test::min_eigenvalue(P_after), -1e-12);
  // The kept landmark now has the smaller uncertainty of the two along the dropped one's ray.
  const int k = 6 + 3 * keep;
  const double before = P.block(k, k, 3, 3).trace();
  EXPECT_LT(ekf_.landmark_covariance(keep).trace(), before);
}

TEST_F(EkfMergeTest, TwoDifferentPointsAreGatedAndNothingChanges) {
  const int a = ekf_.initialize_landmark(100.0, 120.0, 2.0, 0.05);
  const int b = ekf_.initialize_landmark(220.0, 120.0, 2.0, 0.05);  // about 1 m away from a
  ASSERT_GE(a, 0);
  ASSERT_GE(b, 0);
  const Eigen::VectorXd x = ekf_.state();
  const Eigen::MatrixXd P = ekf_.covariance();
  EXPECT_EQ(ekf_.merge_landmarks(a, b, 11.34), cs::ObservationResult::kGate);
  EXPECT_GT(ekf_.last_merge_test_ratio(), 11.34);  // the ratio that was gated
  EXPECT_EQ(ekf_.counters().merges_gated, 1U);
  EXPECT_EQ(ekf_.counters().landmarks_merged, 0U);
  EXPECT_EQ(ekf_.landmark_count(), 2);
  EXPECT_TRUE(ekf_.state() == x);
  EXPECT_TRUE(ekf_.covariance() == P);
  // Without a gate (the track id says they are one point) they are merged all the same.
  EXPECT_EQ(ekf_.merge_landmarks(a, b, 0.0), cs::ObservationResult::kFused);
  EXPECT_EQ(ekf_.landmark_count(), 1);
  EXPECT_FALSE(ekf_.slot_used(b));
  EXPECT_TRUE(ekf_.state().allFinite());
  const int n = ekf_.active_dim();
  const Eigen::MatrixXd P2 = ekf_.covariance().topLeftCorner(n, n);
  EXPECT_EQ(cleanslam::test::asymmetry(P2), 0.0);
  EXPECT_GE(cleanslam::test::min_eigenvalue(P2), -1e-12);
}

TEST_F(EkfMergeTest, UnusedOrEqualSlotsAndBadNoiseAreRefused) {
  const int a = ekf_.initialize_landmark(100.0, 120.0);
  ASSERT_GE(a, 0);
  EXPECT_EQ(ekf_.merge_landmarks(a, a, 0.0), cs::ObservationResult::kInvalidSlot);
  EXPECT_EQ(ekf_.merge_landmarks(a, a + 1, 0.0), cs::ObservationResult::kInvalidSlot);
  EXPECT_EQ(ekf_.merge_landmarks(-1, a, 0.0), cs::ObservationResult::kInvalidSlot);
  EXPECT_EQ(ekf_.merge_landmarks(a, hal::kMaxLandmarks, 0.0), cs::ObservationResult::kInvalidSlot);
  const int b = ekf_.initialize_landmark(101.0, 120.0);
  ASSERT_GE(b, 0);
  const Eigen::VectorXd x2 = ekf_.state();
  ASSERT_EQ(ekf_.merge_landmarks(a, b, 1e-12), cs::ObservationResult::kGate);  // leaves a ratio
  ASSERT_GT(ekf_.last_merge_test_ratio(), 0.0);
  EXPECT_EQ(ekf_.merge_landmarks(a, b, 0.0, std::nan("")), cs::ObservationResult::kInvalidSlot);
  EXPECT_EQ(ekf_.last_merge_test_ratio(), -1.0);
  EXPECT_EQ(ekf_.merge_landmarks(a, b, 0.0, -1.0), cs::ObservationResult::kInvalidSlot);
  EXPECT_TRUE(ekf_.state() == x2);
  EXPECT_EQ(ekf_.landmark_count(), 2);
}

// EkfConfig::merge_considers_kept: the kept entry's rows of the gain are zero (Schmidt). The result
// must equal the Joseph form for that gain, which holds for any gain, leave the kept entry exactly
// as it was, and claim no more than the optimal update.
TEST_F(EkfConsideredMergeTest, EqualsTheDenseSchmidtUpdateAndLeavesTheKeptEntryAsItWas) {
  const double r = 0.01;
  const Scene sc = scene(143.0, 108.0, r);
  ASSERT_GE(sc.keep, 0);
  ASSERT_GE(sc.other, 0);
  ASSERT_GE(sc.drop, 0);
  const int keep = sc.keep;
  const int drop = sc.drop;
  const int n = sc.n;
  const Eigen::VectorXd& x = sc.x;
  const Eigen::MatrixXd& P = sc.P;
  const Eigen::MatrixXd& H = sc.H;
  const Eigen::MatrixXd& R = sc.R;
  const Eigen::MatrixXd& S = sc.S;
  const int k = 6 + 3 * keep;
  const Eigen::MatrixXd K_opt = P * H.transpose() * S.inverse();
  Eigen::MatrixXd K = K_opt;
  K.middleRows<3>(k).setZero();
  const Eigen::Vector3d nu = -(H * x);
  const Eigen::VectorXd x_ref = x + K * nu;
  const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(n, n) - K * H;
  const Eigen::MatrixXd P_ref = IKH * P * IKH.transpose() + K * R * K.transpose();
  const Eigen::MatrixXd P_opt = P - K_opt * S * K_opt.transpose();

  ASSERT_EQ(ekf_.merge_landmarks(keep, drop, 0.0, r), cs::ObservationResult::kFused);
  EXPECT_NEAR(ekf_.last_merge_test_ratio(), nu.dot(S.inverse() * nu), 1e-9);
  EXPECT_FALSE(ekf_.slot_used(drop));
  EXPECT_EQ(ekf_.counters().landmarks_merged, 1U);
  const Eigen::VectorXd x_after = ekf_.state().head(n);
  const Eigen::MatrixXd P_after = ekf_.covariance().topLeftCorner(n, n);
  EXPECT_TRUE(x_after.segment<3>(k) == x.segment<3>(k));
  EXPECT_TRUE((P_after.block<3, 3>(k, k) == P.block<3, 3>(k, k)));
  EXPECT_GT((x_after.head<6>() - x.head<6>()).norm(), 1e-3);  // the robot is what moves
  const int d = 6 + 3 * drop;
  expect_equal_outside(x_after, P_after, x_ref, P_ref, d);
  EXPECT_EQ(cleanslam::test::asymmetry(P_after), 0.0);
  EXPECT_GE(cleanslam::test::min_eigenvalue(P_after), -1e-12);
  Eigen::MatrixXd excess = P_after - P_opt;
  excess.middleRows<3>(d).setZero();
  excess.middleCols<3>(d).setZero();
  EXPECT_GE(cleanslam::test::min_eigenvalue(excess), -1e-12);
  EXPECT_GT(excess.trace(), 1e-6);
}

}  // namespace
