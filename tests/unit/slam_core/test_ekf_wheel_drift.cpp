#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "cleanslam/slam_core/ekf.hpp"
#include "drift_filter.hpp"
#include "symmetric_eigen.hpp"

// The wheel drift state and Ekf::fuse_wheel_gyro_mismatch: z = b dt - c d + noise.
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

constexpr double kDriftStd = cleanslam::test::kDriftFilterDriftStd;
constexpr int kBias = hal::kPoseDim;
constexpr int kDrift = hal::kPoseDim + 2;
using cleanslam::test::drift_config;

hal::Calibration calibration() {
  return cleanslam::test::drift_calibration();
}

void prepare(cs::Ekf& ekf) {
  cleanslam::test::prepare_drift_filter(ekf);
}

cs::OdometryIncrement::WheelGyroMismatch mismatch(double z, double dt, double d, double var) {
  cs::OdometryIncrement::WheelGyroMismatch m;
  m.add(z, dt, d, var);
  return m;
}

}  // namespace

// Found by tests/fuzz/fuzz_ekf.cpp: an information of 1e200 and more (finite) left a variance
// below zero by rounding. Such an update is refused (nothing changed) or fused into a covariance
// whose diagonal stays non-negative.
TEST(EkfWheelDrift, ExtremeInformationNeverLeavesANegativeVariance) {
  int refused = 0;
  for (const double information : {1e200, 1e250, 1e300}) {
    for (const int axis : {0, 1}) {
      cs::Ekf ekf(calibration(), drift_config(false));
      prepare(ekf);
      const Eigen::MatrixXd P0 = ekf.covariance();
      auto m = mismatch(0.3, 0.05, 0.01, 1e-6);
      m.information(axis, axis) = information;
      const cs::ObservationResult r = ekf.fuse_wheel_gyro_mismatch(m, 0.0);
      const int n = ekf.active_dim();
      EXPECT_GE(ekf.covariance().diagonal().head(n).minCoeff(), 0.0) << information << " " << axis;
      if (r == cs::ObservationResult::kNotPositiveDefinite) {
        ++refused;
        EXPECT_EQ(ekf.covariance(), P0);
      } else {
        EXPECT_EQ(r, cs::ObservationResult::kFused);
      }
    }
  }
  EXPECT_GT(refused, 0);
}

// Found by tests/fuzz/fuzz_ekf.cpp: an information vector of 1e300 (finite) made the state
// infinite.
TEST(EkfWheelDrift, UpdateThatWouldOverflowTheStateIsRefused) {
  cs::Ekf ekf(calibration(), drift_config(true));
  prepare(ekf);
  const Eigen::VectorXd x0 = ekf.state();
  const Eigen::MatrixXd P0 = ekf.covariance();
  auto m = mismatch(0.3, 0.05, 0.01, 1e6);  // z = v^T y / sqrt(l) overflows
  m.information_vector << 1e308, -1e308;
  EXPECT_EQ(ekf.fuse_wheel_gyro_mismatch(m, 0.0), cs::ObservationResult::kNotPositiveDefinite);
  EXPECT_EQ(ekf.state(), x0);
  EXPECT_EQ(ekf.covariance(), P0);
}

// Found by tests/fuzz/fuzz_ekf.cpp: a non-finite derivative of the increment in an odometry
// error state, or a non-finite interval, reached the state and the bias variance.
TEST(EkfWheelDrift, PredictRejectsNonFiniteOdometryStateInputs) {
  cs::Ekf ekf(calibration(), drift_config(true));
  prepare(ekf);
  const Eigen::VectorXd x0 = ekf.state();
  const Eigen::MatrixXd P0 = ekf.covariance();
  cs::OdometryIncrement u;
  u.dx_c = Eigen::Vector3d(0.0, 0.0, 0.1);
  u.Q.diagonal().setConstant(1e-5);
  u.dt_s = 0.05;
  for (int k = 0; k < 4; ++k) {
    cs::OdometryIncrement bad = u;
    switch (k) {
      case 0:
        bad.du_dbias(4) = std::nan("");
        break;
      case 1:
        bad.du_dscale(0) = std::numeric_limits<double>::infinity();
        break;
      case 2:
        bad.du_ddrift(4) = std::nan("");
        break;
      default:
        bad.dt_s = std::numeric_limits<double>::infinity();
        break;
    }
    EXPECT_EQ(ekf.predict(bad).result, cs::PredictResult::kNonFinite) << k;
  }
  EXPECT_EQ(ekf.state(), x0);
  EXPECT_EQ(ekf.covariance(), P0);
  EXPECT_TRUE(ekf.predict(u).applied());
}

TEST(EkfWheelDrift, OneMismatchIsTheDenseKalmanUpdate) {
  cs::Ekf ekf(calibration(), drift_config(false));
  prepare(ekf);
  const int n = hal::kPoseDim + 2 * hal::kLandmarkDim;
  const Eigen::VectorXd x = ekf.state().head(n);
  const Eigen::MatrixXd P = ekf.covariance().topLeftCorner(n, n);
  ASSERT_GT(P.block(0, kDrift, 6, 1).norm(), 1e-6);  // the pose is correlated with the drift
  Eigen::RowVectorXd H = Eigen::RowVectorXd::Zero(n);
  H(kBias) = 0.5;
  H(kDrift) = -0.08;
  const double R = 2e-4;
  const double z = 0.01;
  const double S = (H * P * H.transpose())(0, 0) + R;
  const Eigen::VectorXd K = P * H.transpose() / S;
  const Eigen::VectorXd x_ref = x + K * (z - (H * x)(0, 0));
  const Eigen::MatrixXd P_ref = P - K * S * K.transpose();
  ASSERT_EQ(ekf.fuse_wheel_gyro_mismatch(mismatch(z, 0.5, 0.08, R), 16.0),
            cs::ObservationResult::kFused);
  EXPECT_NEAR(ekf.last_mismatch_test_ratio(), (z - (H * x)(0, 0)) * (z - (H * x)(0, 0)) / S, 1e-12);
  // Its status, whitened by the measurement's noise (the eigenvector's sign is free).
  const cs::MismatchStatus& st = ekf.last_mismatch();
  ASSERT_EQ(st.count, 1);
  EXPECT_TRUE(st.updates[0].fused);
  EXPECT_NEAR(std::abs(st.updates[0].innovation), std::abs(z - (H * x)(0, 0)) / std::sqrt(R), 1e-9);
  EXPECT_NEAR(st.updates[0].innovation_variance, S / R, 1e-9);
  EXPECT_NEAR(st.updates[0].test_ratio, ekf.last_mismatch_test_ratio(), 1e-15);
  EXPECT_LT((ekf.state().head(n) - x_ref).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((ekf.covariance().topLeftCorner(n, n) - P_ref).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT((ekf.state().head(6) - x.head(6)).norm(), 1e-6);  // through its correlation with c
  EXPECT_EQ(ekf.counters().wheel_gyro_mismatches_fused, 1U);
}

// A window of intervals is fused as the information it holds about (b, c): the same as the
// batch update with one row per interval.
TEST(EkfWheelDrift, AWindowIsTheDenseBatchUpdateOfItsIntervals) {
  cs::Ekf ekf(calibration(), drift_config(false));
  prepare(ekf);
  const int n = hal::kPoseDim + 2 * hal::kLandmarkDim;
  const Eigen::VectorXd x = ekf.state().head(n);
  const Eigen::MatrixXd P = ekf.covariance().topLeftCorner(n, n);
  constexpr int kRows = 6;
  const double d[kRows] = {0.0, 0.008, 0.01, 0.0, 0.007, 0.002};
  const double z[kRows] = {0.002, -0.001, 0.003, 0.0005, 0.0, 0.001};
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(kRows, n);
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(kRows, kRows);
  Eigen::VectorXd zz(kRows);
  cs::OdometryIncrement::WheelGyroMismatch m;
  for (int k = 0; k < kRows; ++k) {
    const double var = 1.25e-4 + 2e-3 * d[k] * d[k];
    H(k, kBias) = 0.05;
    H(k, kDrift) = -d[k];
    R(k, k) = var;
    zz(k) = z[k];
    m.add(z[k], 0.05, d[k], var);
  }
  ASSERT_EQ(m.intervals, kRows);
  const Eigen::MatrixXd S = H * P * H.transpose() + R;
  const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
  const Eigen::VectorXd predicted = H * x;
  Eigen::VectorXd innovation(kRows);
  for (int k = 0; k < kRows; ++k) {  // a loop: GCC's -Wnull-dereference flags the expression
    innovation(k) = zz(k) - predicted(k);
  }
  const Eigen::VectorXd x_ref = x + K * innovation;
  const Eigen::MatrixXd P_ref = P - K * S * K.transpose();
  ASSERT_EQ(ekf.fuse_wheel_gyro_mismatch(m, 16.0), cs::ObservationResult::kFused);
  EXPECT_LT((ekf.state().head(n) - x_ref).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT((ekf.covariance().topLeftCorner(n, n) - P_ref).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT(ekf.wheel_drift_variance(), P(kDrift, kDrift));
}

TEST(EkfWheelDrift, MismatchesLearnTheBiasAndTheDriftWithHonestVariances) {
  constexpr double kTrueBias = 0.006;
  constexpr double kTrueDrift = -0.14;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> speed(0.0, 0.2);
  double nees = 0.0;
  constexpr int kRuns = 20;
  for (int run = 0; run < kRuns; ++run) {
    cs::Ekf ekf(calibration(), drift_config(true));
    prepare(ekf);
    for (int k = 0; k < 2000; ++k) {
      const double dt = 0.5;
      const double d = (k % 5 == 0 ? 0.0 : speed(rng)) * dt;  // pauses tell b from c
      const double var = 0.05 * 0.05 * dt + 0.3 * 0.3 * d * d / 0.235;
      const double z = kTrueBias * dt - kTrueDrift * d + std::sqrt(var) * noise(rng);
      ASSERT_EQ(ekf.fuse_wheel_gyro_mismatch(mismatch(z, dt, d, var), 0.0),
                cs::ObservationResult::kFused);
    }
    const Eigen::MatrixXd P = ekf.covariance().topLeftCorner(hal::kPoseDim + 6, hal::kPoseDim + 6);
    EXPECT_LT(cleanslam::test::asymmetry(P), 1e-15);
    EXPECT_GT(cleanslam::test::min_eigenvalue(P), -1e-15);
    EXPECT_LT(std::sqrt(ekf.wheel_drift_variance()), 0.1 * kDriftStd);
    Eigen::Vector2d e(ekf.gyro_bias() - kTrueBias, ekf.wheel_drift() - kTrueDrift);
    Eigen::Matrix2d Pe;
    Pe << P(kBias, kBias), P(kBias, kDrift), P(kDrift, kBias), P(kDrift, kDrift);
    nees += e.dot(Pe.inverse() * e) / kRuns;
  }
  // Two degrees of freedom: 2 on average; the 99 % band for the mean of 20 runs is about [1.2, 3].
  EXPECT_GT(nees, 1.0);
  EXPECT_LT(nees, 3.2);
}

TEST(EkfWheelDrift, AnOutlierIsGatedAndBadInputRejectedWithNothingChanged) {
  cs::Ekf ekf(calibration(), drift_config(true));
  prepare(ekf);
  const Eigen::VectorXd x = ekf.state();
  const Eigen::MatrixXd P = ekf.covariance();
  EXPECT_EQ(ekf.fuse_wheel_gyro_mismatch(mismatch(1.0, 0.5, 0.08, 1e-4), 16.0),
            cs::ObservationResult::kGate);
  EXPECT_GT(ekf.last_mismatch_test_ratio(), 16.0);
  ASSERT_EQ(ekf.last_mismatch().count, 1);
  EXPECT_FALSE(ekf.last_mismatch().updates[0].fused);
  EXPECT_EQ(ekf.counters().wheel_gyro_mismatches_gated, 1U);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  cs::OdometryIncrement::WheelGyroMismatch bad = mismatch(0.0, 0.5, 0.08, 1e-4);
  bad.information_vector(1) = nan;
  EXPECT_EQ(ekf.fuse_wheel_gyro_mismatch(bad, 16.0), cs::ObservationResult::kNonFinite);
  bad = mismatch(0.0, 0.5, 0.08, 1e-4);
  bad.information(1, 1) = -1.0;
  EXPECT_EQ(ekf.fuse_wheel_gyro_mismatch(bad, 16.0), cs::ObservationResult::kNonFinite);
  EXPECT_EQ(ekf.counters().rejections[cs::ObservationResult::kNonFinite], 2U);
  // An interval with no variance holds no information and is not counted.
  EXPECT_EQ(mismatch(0.0, 0.5, 0.08, 0.0).intervals, 0);
  EXPECT_EQ(mismatch(0.0, 0.5, 0.08, nan).intervals, 0);
  const cs::OdometryIncrement::WheelGyroMismatch none;
  EXPECT_EQ(ekf.fuse_wheel_gyro_mismatch(none, 16.0), cs::ObservationResult::kInvalidSlot);
  EXPECT_EQ(ekf.last_mismatch().count, 0);
  EXPECT_EQ(ekf.last_mismatch_test_ratio(), -1.0);
  EXPECT_EQ(ekf.state(), x);
  EXPECT_EQ(ekf.covariance(), P);
  EXPECT_EQ(ekf.counters().wheel_gyro_mismatches_fused, 0U);

  cs::EkfConfig no_drift = drift_config(true);
  no_drift.wheel_drift_state = false;
  cs::Ekf plain(calibration(), no_drift);
  EXPECT_EQ(plain.fuse_wheel_gyro_mismatch(mismatch(0.0, 0.5, 0.08, 1e-4), 16.0),
            cs::ObservationResult::kInvalidSlot);
  EXPECT_EQ(plain.wheel_drift_variance(), 0.0);
}
