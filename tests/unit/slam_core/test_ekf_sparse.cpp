#include <cmath>
#include <memory>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "cleanslam/slam_core/camera_frame_measurement.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/prediction_model.hpp"
#include "numeric_jacobian.hpp"

// Mechanisms for sparse landmarks and poor odometry (the sparse-poor-odometry scenario): the gyro
// bias state and the young test on the depth given the pose.
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

constexpr double kBiasStd = 0.005;
constexpr double kBiasWalk = 0.0005;

std::unique_ptr<cs::Ekf> make_ekf(const cs::EkfConfig& config, double pose_var = 1e-4) {
  hal::Calibration calibration;
  calibration.gyro.bias_instability = kBiasStd;
  auto ekf = std::make_unique<cs::Ekf>(calibration, config);
  cs::Vector6d pose;
  pose << 0.3, -0.2, 0.1, 0.01, -0.02, 0.4;
  EXPECT_TRUE(ekf->reset(pose, cs::Matrix6d::Identity() * pose_var));
  return ekf;
}

cs::EkfConfig bias_config() {
  cs::EkfConfig c;
  c.gyro_bias_state = true;
  c.gyro_bias_walk = kBiasWalk;
  return c;
}

cs::OdometryIncrement increment(double distance, double dyaw, double dt) {
  cs::OdometryIncrement u;
  u.dx_c = Eigen::Vector3d(0.01, -0.02, distance);
  u.dpsi_c = Eigen::Vector3d(0.001, -dyaw, 0.002);
  u.Q.diagonal() << 1e-4, 1e-5, 1e-6, 1e-6, 1e-6, 1e-5;
  u.du_dbias << 0.3 * dt * dt, 0.0, -0.05 * dt * dt, 0.0, dt, 0.0;
  u.dt_s = dt;
  return u;
}

// Pose after u with a residual gyro bias b: the mean the filter must follow.
cs::Vector6d pose_after(const cs::Vector6d& pose, double b, const cs::OdometryIncrement& u) {
  return cs::predict_pose(pose, u.dx_c + u.du_dbias.head<3>() * b,
                          u.dpsi_c + u.du_dbias.tail<3>() * b);
}

}  // namespace

TEST(EkfGyroBias, PredictionPropagatesPoseAndBiasWithTheNumericalJacobian) {
  auto ekf = make_ekf(bias_config());
  Eigen::Matrix<double, 7, 7> P = Eigen::Matrix<double, 7, 7>::Zero();
  P.topLeftCorner<6, 6>() = cs::Matrix6d::Identity() * 1e-4;
  P(6, 6) = kBiasStd * kBiasStd;
  EXPECT_NEAR(ekf->gyro_bias_variance(), P(6, 6), 1e-15);
  for (const auto& u : {increment(0.1, 0.3, 0.5), increment(0.05, -0.2, 0.7)}) {
    Eigen::Matrix<double, 7, 1> s;
    s << ekf->camera_pose(), ekf->gyro_bias();
    const auto f = [&u](const Eigen::Matrix<double, 7, 1>& a) {
      Eigen::Matrix<double, 7, 1> out;
      out << pose_after(a.head<6>(), a(6), u), a(6);
      return out;
    };
    const Eigen::Matrix<double, 7, 7> Phi = cleanslam::test::numeric_jacobian<7, 7>(f, s);
    cs::Matrix6d F;
    cs::Matrix6d G;
    cs::prediction_jacobians(s.head<6>(), u.dx_c, u.dpsi_c, F, G);
    Eigen::Matrix<double, 7, 7> Q = Eigen::Matrix<double, 7, 7>::Zero();
    Q.topLeftCorner<6, 6>() = G * u.Q * G.transpose();
    Q(6, 6) = kBiasWalk * kBiasWalk * u.dt_s;
    P = Phi * P * Phi.transpose() + Q;
    ASSERT_TRUE(ekf->predict(u).applied());
    EXPECT_TRUE(ekf->camera_pose().isApprox(f(s).head<6>(), 1e-12));
    // Pose covariance after two steps depends on the pose-bias cross-covariance of the first.
    EXPECT_LT((ekf->pose_covariance() - P.topLeftCorner<6, 6>()).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_NEAR(ekf->gyro_bias_variance(), P(6, 6), 1e-15);
  }
}

// All three odometry error states: the gyro bias, the distance scale and the wheels' drift per
// metre (slot 0's three rows).
TEST(EkfOdometryStates, PredictionPropagatesPoseBiasScaleAndDriftWithTheNumericalJacobian) {
  constexpr double kScaleStd = 0.12;
  constexpr double kDriftStd = 0.5;
  hal::Calibration calibration;
  calibration.gyro.bias_instability = kBiasStd;
  calibration.wheels.scale_error = kScaleStd;
  cs::EkfConfig config = bias_config();
  config.distance_scale_state = true;
  config.wheel_drift_state = true;
  config.wheel_drift_std_rad_per_m = kDriftStd;
  cs::Ekf ekf(calibration, config);
  cs::Vector6d pose0;
  pose0 << 0.3, -0.2, 0.1, 0.01, -0.02, 0.4;
  EXPECT_TRUE(ekf.reset(pose0, cs::Matrix6d::Identity() * 1e-4));
  using Vector9d = Eigen::Matrix<double, 9, 1>;
  using Matrix9d = Eigen::Matrix<double, 9, 9>;
  Matrix9d P = Matrix9d::Zero();
  P.topLeftCorner<6, 6>() = cs::Matrix6d::Identity() * 1e-4;
  P(6, 6) = kBiasStd * kBiasStd;
  P(7, 7) = kScaleStd * kScaleStd;
  P(8, 8) = kDriftStd * kDriftStd;
  EXPECT_NEAR(ekf.distance_scale_variance(), P(7, 7), 1e-15);
  EXPECT_NEAR(ekf.wheel_drift_variance(), P(8, 8), 1e-15);
  for (cs::OdometryIncrement u : {increment(0.1, 0.3, 0.5), increment(0.05, -0.2, 0.7)}) {
    u.du_dscale << u.dx_c, 0.0, 0.0, 0.0;
    u.du_ddrift << 0.2 * u.dx_c(2) * u.dx_c(2), 0.0, 0.0, 0.0, -0.7 * u.dx_c(2), 0.0;
    Vector9d s;
    s << ekf.camera_pose(), ekf.gyro_bias(), ekf.distance_scale(), ekf.wheel_drift();
    const auto f = [&u](const Vector9d& a) {
      const Eigen::Vector3d e = a.tail<3>();
      Eigen::Matrix<double, 6, 3> du_de;
      du_de << u.du_dbias, u.du_dscale, u.du_ddrift;
      const cs::Vector6d d = du_de * e;
      Vector9d out;
      out << cs::predict_pose(a.head<6>(), u.dx_c + d.head<3>(), u.dpsi_c + d.tail<3>()), e;
      return out;
    };
    const Matrix9d Phi = cleanslam::test::numeric_jacobian<9, 9>(f, s);
    cs::Matrix6d F;
    cs::Matrix6d G;
    cs::prediction_jacobians(s.head<6>(), u.dx_c, u.dpsi_c, F, G);
    Matrix9d Q = Matrix9d::Zero();
    Q.topLeftCorner<6, 6>() = G * u.Q * G.transpose();
    Q(6, 6) = kBiasWalk * kBiasWalk * u.dt_s;
    P = Phi * P * Phi.transpose() + Q;
    ASSERT_TRUE(ekf.predict(u).applied());
    EXPECT_TRUE(ekf.camera_pose().isApprox(f(s).head<6>(), 1e-12));
    // The second step's pose covariance depends on the first's cross-covariances.
    EXPECT_LT((ekf.pose_covariance() - P.topLeftCorner<6, 6>()).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT((ekf.covariance().block<6, 3>(0, 6) - P.block<6, 3>(0, 6)).cwiseAbs().maxCoeff(),
              1e-9);
    EXPECT_NEAR(ekf.gyro_bias_variance(), P(6, 6), 1e-15);
    EXPECT_NEAR(ekf.distance_scale_variance(), P(7, 7), 1e-15);
    EXPECT_NEAR(ekf.wheel_drift_variance(), P(8, 8), 1e-15);
  }
}

TEST(EkfDistanceScale, AloneItTakesSlotZeroAndLeavesTheBiasAtZero) {
  hal::Calibration calibration;
  calibration.wheels.distance_noise = 0.2;  // the prior when scale_error is not stated
  cs::EkfConfig config;
  config.distance_scale_state = true;
  cs::Ekf ekf(calibration, config);
  EXPECT_TRUE(ekf.reset(cs::Vector6d::Zero(), cs::Matrix6d::Identity() * 1e-4));
  EXPECT_NEAR(ekf.distance_scale_variance(), 0.04, 1e-15);
  EXPECT_EQ(ekf.gyro_bias_variance(), 0.0);
  EXPECT_EQ(ekf.initialize_landmark(100.0, 80.0), 1);
  cs::OdometryIncrement u = increment(0.1, 0.3, 0.5);
  u.du_dscale << u.dx_c, 0.0, 0.0, 0.0;
  ASSERT_TRUE(ekf.predict(u).applied());
  EXPECT_EQ(ekf.gyro_bias(), 0.0);
  EXPECT_EQ(ekf.gyro_bias_variance(), 0.0);
}

TEST(EkfGyroBias, WithoutTheStateDuDbiasIsIgnoredAndSlotZeroIsFree) {
  auto plain = make_ekf(cs::EkfConfig{});
  auto biased = make_ekf(bias_config());
  const cs::OdometryIncrement u = increment(0.1, 0.3, 0.5);
  cs::OdometryIncrement no_bias = u;
  no_bias.du_dbias.setZero();
  auto reference = make_ekf(cs::EkfConfig{});
  ASSERT_TRUE(plain->predict(u).applied());
  ASSERT_TRUE(reference->predict(no_bias).applied());
  EXPECT_EQ(plain->pose_covariance(), reference->pose_covariance());
  EXPECT_EQ(plain->gyro_bias_variance(), 0.0);
  EXPECT_EQ(plain->initialize_landmark(100.0, 80.0), 0);
  // Slot 0 holds the bias: landmarks start at 1, and the bias row is not a landmark.
  EXPECT_EQ(biased->initialize_landmark(100.0, 80.0), 1);
  EXPECT_FALSE(biased->slot_used(0));
  EXPECT_EQ(biased->landmark_count(), 1);
}

TEST(EkfGyroBias, ALandmarkSeenWhileTurningOnTheSpotEstimatesTheBias) {
  cs::EkfConfig c = bias_config();
  auto ekf = make_ekf(c, 1e-8);
  const cs::Vector6d truth = ekf->camera_pose();
  // A known landmark 3 m ahead.
  const int slot = ekf->initialize_landmark(160.0, 120.0, 3.0, 0.01);
  ASSERT_GE(slot, 1);
  const Eigen::Vector3d y = ekf->landmark(slot);
  // The gyro reads a bias of 0.004 rad/s that the dead reckoner did not remove: the increments
  // claim a rotation of 0.004 dt the camera did not make.
  constexpr double kTrueBias = 0.004;
  constexpr double kDt = 0.5;
  for (int k = 0; k < 400; ++k) {
    cs::OdometryIncrement u;
    u.dpsi_c = Eigen::Vector3d(0.0, kTrueBias * kDt, 0.0);
    u.du_dbias << 0.0, 0.0, 0.0, 0.0, -kDt, 0.0;
    u.Q.diagonal() << 1e-8, 1e-8, 1e-8, 1e-8, 1e-6, 1e-8;
    u.dt_s = kDt;
    ASSERT_TRUE(ekf->predict(u).applied());
    Eigen::Vector2d px;
    ASSERT_TRUE(ekf->camera().project(cs::predict_camera_point(truth, y), px, nullptr));
    const cs::Observation o{slot, px.x(), px.y()};
    ekf->update(&o, 1);
  }
  EXPECT_NEAR(ekf->gyro_bias(), kTrueBias, 3.0 * std::sqrt(ekf->gyro_bias_variance()));
  EXPECT_LT(std::sqrt(ekf->gyro_bias_variance()), 0.3 * kBiasStd);
  EXPECT_GT(ekf->gyro_bias(), 0.5 * kTrueBias);
}
