#include <array>
#include <cmath>
#include <span>

#include <gtest/gtest.h>

#include "cleanslam/slam_core/camera_frame_measurement.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/pose_solve.hpp"
#include "numeric_jacobian.hpp"
#include "pose_solve_scenario.hpp"

// solve_planar_pose and the update linearized at its pose
// (EkfConfig::solve_pose_beyond_linear_range).
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;
using cleanslam::test::numeric_jacobian;

namespace {

cs::Vector6d a_pose() {
  cs::Vector6d p;
  p << 0.4, -0.3, 0.1, 0.02, -0.03, 0.7;
  return p;
}

cs::Vector6d planar(const cs::Vector6d& pose, const Eigen::Vector3d& q) {
  cs::Vector6d p = pose;
  p(0) = q(0);
  p(1) = q(1);
  p(5) = q(2);
  return p;
}

// Landmarks ahead of a_pose() and their exact rays from it.
std::array<cs::PoseSighting, 5> sightings_from(const cs::Vector6d& pose) {
  const std::array<Eigen::Vector3d, 5> c = {
      Eigen::Vector3d(2.0, 0.3, 0.2), Eigen::Vector3d(1.5, -0.6, -0.1),
      Eigen::Vector3d(3.0, 0.9, 0.5), Eigen::Vector3d(2.5, -0.2, 0.4),
      Eigen::Vector3d(1.2, 0.1, -0.3)};
  std::array<cs::PoseSighting, 5> s{};
  for (std::size_t i = 0; i < c.size(); ++i) {
    s[i].y = cs::landmark_from_camera_point(pose, c[i], nullptr);
    s[i].Pyy = Eigen::Matrix3d::Identity() * 1e-6;
    s[i].ct = c[i] / c[i].x();
  }
  return s;
}

}  // namespace

TEST(PoseSolve, SightingResidualJacobiansMatchNumeric) {
  const cs::Vector6d pose = a_pose();
  const Eigen::Vector3d y(2.0, 1.0, 0.5);
  const Eigen::Vector3d ct(1.0, 0.2, -0.1);
  Eigen::Matrix3d Jq;
  Eigen::Matrix3d Jy;
  const Eigen::Vector3d r = cs::sighting_residual(pose, y, ct, &Jq, &Jy);
  const Eigen::Vector3d q(pose(0), pose(1), pose(5));
  const auto fq = [&](const Eigen::Vector3d& v) {
    return cs::sighting_residual(planar(pose, v), y, ct);
  };
  const auto fy = [&](const Eigen::Vector3d& v) { return cs::sighting_residual(pose, v, ct); };
  EXPECT_TRUE(Jq.isApprox(numeric_jacobian<3, 3>(fq, q), 1e-7));
  EXPECT_TRUE(Jy.isApprox(numeric_jacobian<3, 3>(fy, y), 1e-7));
  EXPECT_NEAR(r.dot(ct.normalized()), 0.0, 1e-12);  // across the ray only
  // A landmark on the measured ray leaves no residual.
  const Eigen::Vector3d on_ray = cs::landmark_from_camera_point(pose, 2.0 * ct, nullptr);
  EXPECT_LT(cs::sighting_residual(pose, on_ray, ct).norm(), 1e-12);
}

TEST(PoseSolve, SightingCovarianceIsTheLandmarksPlusTheMeasurementsAndRejectsBehind) {
  const cs::Vector6d pose = a_pose();
  cs::PoseSighting s;
  s.ct = Eigen::Vector3d(1.0, 0.1, 0.0);
  s.Pyy = Eigen::Vector3d(0.01, 0.02, 0.03).asDiagonal();
  const cs::SightingNoise noise;
  const Eigen::Vector3d y = cs::landmark_from_camera_point(pose, 2.0 * s.ct, nullptr);
  Eigen::Matrix3d S;
  ASSERT_TRUE(cs::sighting_covariance(pose, y, s, noise, S));
  const Eigen::Matrix3d C = cs::rotation_zyx(pose(3), pose(4), pose(5));
  const double depth = 2.0 * s.ct.norm();
  const Eigen::Matrix3d expected =
      C.transpose() * s.Pyy * C +
      cs::measurement_covariance(s.ct, noise.eps_ct_m, depth * noise.eps_px / noise.focal_px);
  EXPECT_TRUE(S.isApprox(expected, 1e-12));
  const Eigen::Vector3d behind = cs::landmark_from_camera_point(pose, -2.0 * s.ct, nullptr);
  EXPECT_FALSE(cs::sighting_covariance(pose, behind, s, noise, S));
}

TEST(PoseSolve, ConditionalLandmarkMovesWithThePlanarPose) {
  cs::PoseSighting s;
  s.y = Eigen::Vector3d(1.0, 2.0, 0.5);
  s.G << 1.0, 0.0, -0.5, 0.0, 1.0, 0.25, 0.0, 0.0, 0.0;
  const cs::Vector6d prior = a_pose();
  cs::Vector6d moved = prior;
  moved(0) += 0.2;
  moved(1) -= 0.1;
  moved(5) += 0.4;
  EXPECT_TRUE(cs::conditional_landmark(s, prior, prior).isApprox(s.y));
  EXPECT_TRUE(cs::conditional_landmark(s, prior, moved)
                  .isApprox(s.y + s.G * Eigen::Vector3d(0.2, -0.1, 0.4), 1e-12));
}

TEST(PoseSolve, FindsThePoseTheSightingsWereTakenFrom) {
  const cs::Vector6d truth = a_pose();
  const auto s = sightings_from(truth);
  cs::Vector6d prior = truth;
  prior(0) += 0.5;
  prior(1) -= 0.4;
  prior(5) += 0.3;
  const Eigen::Matrix3d P0 = Eigen::Vector3d(1.0, 1.0, 0.5).asDiagonal();
  cs::Vector6d pose;
  cs::PoseFit fit;
  ASSERT_TRUE(cs::solve_planar_pose(prior, P0, s, cs::SightingNoise{}, pose, fit));
  EXPECT_LT((pose.head<2>() - truth.head<2>()).norm(), 2e-3);
  EXPECT_NEAR(pose(5), truth(5), 1e-3);
  EXPECT_EQ(pose.segment<3>(2), prior.segment<3>(2));  // z, roll, pitch stay the prior's
  EXPECT_EQ(fit.sightings, 5);
  EXPECT_LT(fit.sightings_cost, 0.1);
  EXPECT_GT(fit.prior_cost, 0.5);
  // Nothing to solve against, or a prior that is no covariance: no pose.
  cs::Vector6d untouched = prior;
  EXPECT_FALSE(cs::solve_planar_pose(prior, P0, std::span<const cs::PoseSighting>(),
                                     cs::SightingNoise{}, untouched, fit));
  EXPECT_FALSE(cs::solve_planar_pose(prior, -P0, s, cs::SightingNoise{}, untouched, fit));
  EXPECT_EQ(untouched, prior);
}

TEST(PoseSolve, ALandmarkMappedFromThePoseTellsNothing) {
  // Each landmark's prior given the pose moves rigidly with it (as one mapped from that pose):
  // the sightings fit any pose equally well and the prior's pose stays.
  const cs::Vector6d prior = a_pose();
  auto s = sightings_from(prior);
  for (auto& si : s) {
    si.G.col(0) = Eigen::Vector3d::UnitX();
    si.G.col(1) = Eigen::Vector3d::UnitY();
    si.G.col(2) = Eigen::Vector3d(-(si.y.y() - prior(1)), si.y.x() - prior(0), 0.0);
  }
  cs::Vector6d pose;
  cs::PoseFit fit;
  ASSERT_TRUE(
      cs::solve_planar_pose(prior, Eigen::Matrix3d::Identity(), s, cs::SightingNoise{}, pose, fit));
  EXPECT_LT((pose - prior).norm(), 1e-6);
}

TEST(PoseSolve, UpdateStartsFromTheSolvedPoseOnlyBeyondTheLinearRange) {
  const hal::Calibration calibration;
  cs::EkfConfig on;
  cs::EkfConfig off;
  off.solve_pose_beyond_linear_range = false;
  const Eigen::Vector3d offset(0.35, -0.3, 0.25);
  // Lost (0.4 m, 0.3 rad; no landmark young): linearized at the solved pose, the update lands at
  // the truth; the prior's linearization does not.
  cs::Ekf a(calibration, on);
  cs::Ekf b(calibration, off);
  const auto sa = cleanslam::test::make_pose_solve_scenario(a, 0.4, 0.3, offset);
  const auto sb = cleanslam::test::make_pose_solve_scenario(b, 0.4, 0.3, offset);
  ASSERT_EQ(sa.count, 4);
  a.update(sa.obs.data(), sa.count);
  b.update(sb.obs.data(), sb.count);
  EXPECT_EQ(a.counters().pose_solves, 1U);
  EXPECT_EQ(b.counters().pose_solves, 0U);
  const double ea = (a.camera_pose().head<2>() - sa.truth.head<2>()).norm();
  const double eb = (b.camera_pose().head<2>() - sb.truth.head<2>()).norm();
  EXPECT_LT(ea, 0.02);
  EXPECT_GT(eb, 3.0 * ea);
  EXPECT_NEAR(a.camera_pose()(5), sa.truth(5), 0.01);
  // Certain (1 cm, 1 mrad): the prior's linearization holds and the update is the plain one.
  cs::Ekf c(calibration, on);
  cs::Ekf d(calibration, off);
  const Eigen::Vector3d small(0.01, -0.01, 0.001);
  const auto sc = cleanslam::test::make_pose_solve_scenario(c, 0.01, 0.001, small);
  const auto sd = cleanslam::test::make_pose_solve_scenario(d, 0.01, 0.001, small);
  c.update(sc.obs.data(), sc.count);
  d.update(sd.obs.data(), sd.count);
  EXPECT_EQ(c.counters().pose_solves, 0U);
  EXPECT_EQ(c.state(), d.state());
  EXPECT_EQ(c.covariance(), d.covariance());
}

TEST(PoseSolve, TwoSightingsOrOnesThatDoNotFitAreNoPlaceToLinearizeAt) {
  const hal::Calibration calibration;
  const Eigen::Vector3d offset(0.35, -0.3, 0.25);
  for (std::size_t i = 0; i < 4; ++i) {
    for (std::size_t j = i; j < 4; ++j) {
      cs::Ekf a(calibration, cs::EkfConfig{});
      const auto sa = cleanslam::test::make_pose_solve_scenario(a, 0.5, 0.3, offset);
      const std::array<cs::Observation, 2> pair = {sa.obs[i], sa.obs[j]};
      a.update(pair.data(), i == j ? 1 : 2);
      EXPECT_EQ(a.counters().pose_solves, 0U) << "sightings " << i << ", " << j;
    }
  }
  // Two sightings swapped between their landmarks: no pose explains both.
  cs::Ekf b(calibration, cs::EkfConfig{});
  auto sb = cleanslam::test::make_pose_solve_scenario(b, 0.5, 0.3, offset);
  std::swap(sb.obs[0].slot, sb.obs[1].slot);
  b.update(sb.obs.data(), sb.count);
  EXPECT_EQ(b.counters().pose_solves, 0U);
}
