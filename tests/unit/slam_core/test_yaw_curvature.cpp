#include <cmath>
#include <memory>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "cleanslam/slam_core/camera_frame_measurement.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/yaw_curvature.hpp"
#include "symmetric_eigen.hpp"

// The second-order yaw terms of eq. 21 (EkfConfig::second_order_yaw).
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

cs::Vector6d a_pose() {
  cs::Vector6d pose;
  pose << 0.4, -0.3, 0.1, 0.02, -0.03, 0.7;
  return pose;
}

// h as a function of w = (y - x_vp, yaw), the other pose components held.
Eigen::Vector3d h_of(const cs::Vector6d& pose, const Eigen::Vector4d& w) {
  cs::Vector6d p = pose;
  p(5) = w(3);
  return cs::predict_camera_point(p, p.head<3>() + w.head<3>());
}

}  // namespace

TEST(YawCurvature, HessiansAreTheNumericalSecondDerivatives) {
  const cs::Vector6d pose = a_pose();
  const Eigen::Vector3d y(2.0, 1.5, 0.3);
  Eigen::Matrix4d H[3];
  cs::camera_point_yaw_hessians(pose, y, H);
  Eigen::Vector4d w0;
  w0 << y - pose.head<3>(), pose(5);
  constexpr double kStep = 1e-4;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      Eigen::Vector4d di = Eigen::Vector4d::Zero();
      Eigen::Vector4d dj = Eigen::Vector4d::Zero();
      di(i) = kStep;
      dj(j) = kStep;
      const Eigen::Vector3d d2 = (h_of(pose, w0 + di + dj) - h_of(pose, w0 + di - dj) -
                                  h_of(pose, w0 - di + dj) + h_of(pose, w0 - di - dj)) /
                                 (4.0 * kStep * kStep);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(H[k](i, j), d2(k), 1e-6) << "k " << k << " (" << i << ", " << j << ")";
      }
    }
  }
  // h is linear in y - x_vp: only the yaw row and column are not zero.
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE((H[k].topLeftCorner<3, 3>().isZero(0.0)));
  }
}

TEST(YawCurvature, CovarianceIsThatOfTheSecondOrderTermsOfAGaussian) {
  // For w ~ N(0, Q) the quadratic part 1/2 w^T H_k w has the covariance 1/2 tr(H_k Q H_l Q):
  // checked against samples.
  const cs::Vector6d pose = a_pose();
  const Eigen::Vector3d y(2.0, 1.5, 0.3);
  Eigen::Matrix4d A;
  A << 0.8, 0.0, 0.0, 0.0, 0.3, 0.5, 0.0, 0.0, -0.1, 0.2, 0.1, 0.0, 0.05, -0.2, 0.0, 0.4;
  const Eigen::Matrix4d Q = A * A.transpose();
  const Eigen::Matrix3d C = cs::yaw_curvature_covariance(pose, y, Q);
  Eigen::Matrix4d H[3];
  cs::camera_point_yaw_hessians(pose, y, H);
  std::mt19937 rng(5);
  std::normal_distribution<double> n01;
  constexpr int kSamples = 200000;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (int s = 0; s < kSamples; ++s) {
    const Eigen::Vector4d w = A * Eigen::Vector4d(n01(rng), n01(rng), n01(rng), n01(rng));
    const Eigen::Vector3d q(0.5 * w.dot(H[0] * w), 0.5 * w.dot(H[1] * w), 0.5 * w.dot(H[2] * w));
    mean += q;
    second += q * q.transpose();
  }
  mean /= kSamples;
  const Eigen::Matrix3d sampled = second / kSamples - mean * mean.transpose();
  EXPECT_LT((sampled - C).cwiseAbs().maxCoeff(), 0.03 * C.cwiseAbs().maxCoeff())
      << sampled << "\n\n"
      << C;
  EXPECT_GT(cleanslam::test::min_eigenvalue(C), -1e-12);
}

TEST(YawCurvature, TheEkfAddsItToTheInnovationCovarianceOnlyWhenConfigured) {
  const hal::Calibration calibration;
  cs::Matrix6d P0 = cs::Matrix6d::Identity() * 1e-3;
  P0(5, 5) = 0.3 * 0.3;  // a yaw known to 17 degrees
  const auto make = [&](bool second_order) {
    cs::EkfConfig config;
    config.second_order_yaw = second_order;
    auto ekf = std::make_unique<cs::Ekf>(calibration, config);
    EXPECT_TRUE(ekf->reset(a_pose(), P0));
    EXPECT_EQ(ekf->initialize_landmark(170.0, 110.0), 0);
    return ekf;
  };
  // The term, from the prior both runs share.
  const auto prior = make(false);
  const Eigen::MatrixXd& P = prior->covariance();
  constexpr int kLm = 6;
  Eigen::Matrix4d Q;
  Q.topLeftCorner<3, 3>() =
      P.block<3, 3>(kLm, kLm) - P.block<3, 3>(kLm, 0) - P.block<3, 3>(0, kLm) + P.block<3, 3>(0, 0);
  const Eigen::Vector3d c = P.block<3, 1>(kLm, 5) - P.block<3, 1>(0, 5);
  Q.block<3, 1>(0, 3) = c;
  Q.block<1, 3>(3, 0) = c.transpose();
  Q(3, 3) = P(5, 5);
  const Eigen::Matrix3d extra =
      cs::yaw_curvature_covariance(prior->camera_pose(), prior->landmark(0), Q);
  const cs::Observation o{0, 180.0, 112.0};
  const Eigen::Matrix3d S_off = make(false)->update(&o, 1).observations[0].innovation_covariance;
  const Eigen::Matrix3d S_on = make(true)->update(&o, 1).observations[0].innovation_covariance;
  EXPECT_GT(extra.norm(), 1e-3 * S_off.norm());
  EXPECT_LT((S_on - S_off - extra).cwiseAbs().maxCoeff(), 1e-9 * S_on.cwiseAbs().maxCoeff());
}
