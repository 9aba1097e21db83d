#include <array>
#include <cmath>
#include <memory>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "cleanslam/slam_core/camera_frame_measurement.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/prediction_model.hpp"
#include "ekf_dense_reference.hpp"

// The consider (Schmidt) update of young landmarks and the depth bounds of an update.
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

std::unique_ptr<cs::Ekf> make_ekf(const cs::EkfConfig& config) {
  hal::Calibration calibration;
  auto ekf = std::make_unique<cs::Ekf>(calibration, config);
  cs::Vector6d pose;
  pose << 0.3, -0.2, 0.1, 0.01, -0.02, 0.4;
  cs::Vector6d d;
  d << 1e-4, 1e-4, 1e-6, 1e-6, 1e-6, 1e-4;
  EXPECT_TRUE(ekf->reset(pose, d.asDiagonal()));
  return ekf;
}

void move(cs::Ekf& ekf, double distance, double dyaw) {
  cs::OdometryIncrement u;
  u.dx_c = Eigen::Vector3d(distance, 0.0, 0.0);
  u.dpsi_c = Eigen::Vector3d(0.0, 0.0, dyaw);
  u.Q.diagonal() << 1e-4, 1e-5, 1e-6, 1e-6, 1e-6, 1e-5;
  ASSERT_TRUE(ekf.predict(u).applied());
}

Eigen::Vector2d seen_from(const cs::Ekf& ekf, const cs::Vector6d& pose, int slot) {
  Eigen::Vector2d px;
  EXPECT_TRUE(
      ekf.camera().project(cs::predict_camera_point(pose, ekf.landmark(slot)), px, nullptr));
  return px;
}

// Dense reference of one batch update with gain K = P H^T S^-1 whose rows outside each young
// observation's own landmark are zeroed in that observation's columns; Joseph form.
void dense_update(const cs::Ekf& ekf, const cs::Observation* obs, int m,
                  const std::array<bool, 8>& young, Eigen::VectorXd& x_out,
                  Eigen::MatrixXd& P_out) {
  const int n = ekf.active_dim();
  const Eigen::MatrixXd P = ekf.covariance().topLeftCorner(n, n);
  const Eigen::VectorXd x = ekf.state().head(n);
  Eigen::MatrixXd H;
  Eigen::MatrixXd R;
  Eigen::VectorXd nu;
  ASSERT_TRUE(cleanslam::test::stack_observations(ekf, obs, m, nu, R, H));
  const Eigen::MatrixXd S = H * P * H.transpose() + R;
  Eigen::MatrixXd K = P * H.transpose() * S.inverse();
  for (int i = 0; i < m; ++i) {
    if (!young[static_cast<std::size_t>(i)]) {
      continue;
    }
    const int lm = 6 + 3 * obs[i].slot;
    for (int r = 0; r < n; ++r) {
      if (r < lm || r >= lm + 3) {
        K.block(r, 3 * i, 1, 3).setZero();
      }
    }
  }
  const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(n, n) - K * H;
  P_out = IKH * P * IKH.transpose() + K * R * K.transpose();
  x_out = x + K * nu;
}

}  // namespace

TEST(EkfConsider, FreshLandmarkIsYoungUntilItsDepthConverges) {
  cs::EkfConfig c;
  auto ekf = make_ekf(c);
  const int slot = ekf->initialize_landmark(100.0, 80.0);
  ASSERT_GE(slot, 0);
  // eps_ct 30 m at an assumed depth of 5 m: the relative depth std. dev. is about 6.
  EXPECT_GT(ekf->relative_depth_std(slot), 1.0);
  EXPECT_TRUE(ekf->young(slot));
  const int known = ekf->initialize_landmark(200.0, 150.0, 3.0, 0.05);
  ASSERT_GE(known, 0);
  EXPECT_LT(ekf->relative_depth_std(known), c.young_depth_std_fraction);
  EXPECT_FALSE(ekf->young(known));
  EXPECT_LT(ekf->relative_depth_std(7), 0.0);
  c.consider_young_landmarks = false;
  auto off = make_ekf(c);
  ASSERT_GE(off->initialize_landmark(100.0, 80.0), 0);
  EXPECT_FALSE(off->young(0));
}

TEST(EkfConsider, YoungObservationsUpdateOnlyTheirLandmarkAndMatchMaskedJoseph) {
  cs::EkfConfig c;
  c.depth_bounds = false;     // the dense reference has none
  c.invariant_reset = false;  // nor the invariant reset (test_ekf_invariant_reset.cpp)
  auto ekf = make_ekf(c);
  // Two mature landmarks (depth known) and two young ones.
  ASSERT_EQ(ekf->initialize_landmark(60.0, 60.0, 3.0, 0.02), 0);
  ASSERT_EQ(ekf->initialize_landmark(250.0, 70.0, 4.0, 0.02), 1);
  ASSERT_EQ(ekf->initialize_landmark(120.0, 180.0), 2);
  ASSERT_EQ(ekf->initialize_landmark(220.0, 170.0), 3);
  move(*ekf, 0.3, 0.1);
  cs::Vector6d from = ekf->camera_pose();
  from(1) += 0.005;
  from(5) += 0.002;
  std::array<cs::Observation, 4> obs{};
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d px = seen_from(*ekf, from, i);
    obs[static_cast<std::size_t>(i)] = {i, px.x(), px.y()};
  }
  const std::array<bool, 8> young{false, false, true, true};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(ekf->young(i), young[static_cast<std::size_t>(i)]) << i;
  }
  Eigen::VectorXd x_expected;
  Eigen::MatrixXd P_expected;
  dense_update(*ekf, obs.data(), 4, young, x_expected, P_expected);
  const int n = ekf->active_dim();
  const cs::UpdateStatus& st = ekf->update(obs.data(), 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(st.observations[static_cast<std::size_t>(i)].fused())
        << i << " " << cs::to_string(st.observations[static_cast<std::size_t>(i)].result);
  }
  ASSERT_TRUE(st.applied);
  EXPECT_EQ(st.fused, 4);
  EXPECT_EQ(ekf->counters().consider_observations, 2U);
  Eigen::VectorXd dx = ekf->state().head(n) - x_expected;
  dx(3) = cs::wrap_angle(dx(3));
  dx(5) = cs::wrap_angle(dx(5));
  EXPECT_LT(dx.cwiseAbs().maxCoeff(), 1e-9);
  const double scale = P_expected.cwiseAbs().maxCoeff();
  EXPECT_LT((ekf->covariance().topLeftCorner(n, n) - P_expected).cwiseAbs().maxCoeff(),
            1e-9 * scale);
}

TEST(EkfConsider, OnlyYoungObservationsLeavePoseAndOtherLandmarksUnchanged) {
  cs::EkfConfig c;
  auto ekf = make_ekf(c);
  ASSERT_EQ(ekf->initialize_landmark(60.0, 60.0, 3.0, 0.02), 0);
  ASSERT_EQ(ekf->initialize_landmark(120.0, 180.0), 1);
  ASSERT_EQ(ekf->initialize_landmark(220.0, 170.0), 2);
  move(*ekf, 0.3, 0.1);
  cs::Vector6d from = ekf->camera_pose();
  from(1) += 0.03;
  std::array<cs::Observation, 2> obs{};
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector2d px = seen_from(*ekf, from, i + 1);
    obs[static_cast<std::size_t>(i)] = {i + 1, px.x(), px.y()};
  }
  const cs::Vector6d pose0 = ekf->camera_pose();
  const cs::Matrix6d Pp0 = ekf->pose_covariance();
  const Eigen::Vector3d l0 = ekf->landmark(0);
  const Eigen::Matrix3d Pl0 = ekf->landmark_covariance(0);
  const Eigen::Vector3d l1 = ekf->landmark(1);
  const cs::UpdateStatus& st = ekf->update(obs.data(), 2);
  ASSERT_TRUE(st.applied);
  EXPECT_EQ(st.fused, 2);
  EXPECT_EQ(ekf->camera_pose(), pose0);
  EXPECT_LT((ekf->pose_covariance() - Pp0).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(ekf->landmark(0), l0);
  EXPECT_LT((ekf->landmark_covariance(0) - Pl0).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_GT((ekf->landmark(1) - l1).norm(), 1e-3);  // the young landmark itself moved

  // Without the switch the same observations correct the pose.
  c.consider_young_landmarks = false;
  auto full = make_ekf(c);
  ASSERT_EQ(full->initialize_landmark(60.0, 60.0, 3.0, 0.02), 0);
  ASSERT_EQ(full->initialize_landmark(120.0, 180.0), 1);
  ASSERT_EQ(full->initialize_landmark(220.0, 170.0), 2);
  move(*full, 0.3, 0.1);
  ASSERT_TRUE(full->update(obs.data(), 2).applied);
  EXPECT_GT((full->camera_pose() - pose0).norm(), 1e-6);
}

TEST(EkfDepthBound, NoLandmarkIsFusedBehindTheCameraOrBeyondMaxDepth) {
  cs::EkfConfig c;
  c.consider_young_landmarks = false;
  c.gate_chi2 = 1e9;  // let wild observations through the gates: only the bound stops them
  c.gate_pixel_chi2 = 0.0;
  c.max_depth_m = 8.0;
  auto ekf = make_ekf(c);
  int bounded = 0;
  int fused = 0;
  for (int trial = 0; trial < 40; ++trial) {
    ekf = make_ekf(c);
    const double u0 = 40.0 + 6.0 * trial;
    const int slot = ekf->initialize_landmark(u0, 120.0);
    ASSERT_GE(slot, 0);
    move(*ekf, 0.4, 0.0);
    // Pixels far across the image: a huge parallax that the linearized update turns into a
    // depth behind the camera or far beyond the room.
    for (int k = 0; k < 4; ++k) {
      cs::Observation o{slot, 319.0 - u0 + 3.0 * k, 120.0 + 25.0 * k};
      const cs::UpdateStatus& st = ekf->update(&o, 1);
      if (st.observations[0].result == cs::ObservationResult::kDepthBound) {
        ++bounded;
        EXPECT_FALSE(st.applied);
      }
      if (st.fused > 0) {
        ++fused;
        const Eigen::Vector3d h = cs::predict_camera_point(ekf->camera_pose(), ekf->landmark(slot));
        EXPECT_GT(h.x(), c.min_depth_m);
        EXPECT_LE(h.x(), c.max_depth_m);
      }
    }
  }
  EXPECT_GT(bounded, 0);
  EXPECT_GT(fused, 0);
}

TEST(EkfDepthBound, OnlyTheViolatingObservationIsDroppedFromABatch) {
  cs::EkfConfig c;
  c.consider_young_landmarks = false;
  c.gate_chi2 = 1e9;
  c.gate_pixel_chi2 = 0.0;
  c.max_depth_m = 6.0;
  auto ekf = make_ekf(c);
  ASSERT_EQ(ekf->initialize_landmark(100.0, 100.0, 3.0, 0.05), 0);
  ASSERT_EQ(ekf->initialize_landmark(200.0, 120.0), 1);  // assumed depth 5 m, young
  // Landmark 1 seen from the moved camera where the point at 20 m along its first ray is: the
  // parallax pushes its depth past 6 m.
  const cs::Vector6d pose0 = ekf->camera_pose();
  const Eigen::Vector3d far = pose0.head<3>() + 4.0 * (ekf->landmark(1) - pose0.head<3>());
  move(*ekf, 0.2, 0.0);
  const cs::Vector6d pose = ekf->camera_pose();
  const Eigen::Vector2d p0 = seen_from(*ekf, pose, 0);
  Eigen::Vector2d p1;
  ASSERT_TRUE(ekf->camera().project(cs::predict_camera_point(pose, far), p1, nullptr));
  std::array<cs::Observation, 2> obs{{{0, p0.x() + 0.3, p0.y()}, {1, p1.x(), p1.y()}}};
  const cs::UpdateStatus& st = ekf->update(obs.data(), 2);
  EXPECT_EQ(st.observations[1].result, cs::ObservationResult::kDepthBound);
  EXPECT_TRUE(st.observations[0].fused());
  EXPECT_TRUE(st.applied);
  EXPECT_EQ(st.fused, 1);
  EXPECT_EQ(st.rejected, 1);
  EXPECT_EQ(ekf->counters().rejections[cs::ObservationResult::kDepthBound], 1U);
  EXPECT_LE(cs::predict_camera_point(ekf->camera_pose(), ekf->landmark(1)).x(), 6.0);
}
