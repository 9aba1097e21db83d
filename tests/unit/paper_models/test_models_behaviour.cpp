#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "cleanslam/paper_models/comparison_scenario.hpp"
#include "cleanslam/paper_models/conventional_model.hpp"
#include "cleanslam/paper_models/inverse_depth_model.hpp"
#include "cleanslam/paper_models/multi_hypothesis_model.hpp"
#include "cleanslam/paper_models/ray_gaussian.hpp"
#include "symmetric_eigen.hpp"

namespace cleanslam::paper_models {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(RayGaussian, IsWideAlongTheRayAndNarrowAcrossIt) {
  KnownPose pose;
  pose.position_w = {1.0, 2.0, 0.5};
  const Pinhole camera;
  const Gaussian3 g = ray_gaussian_w(camera, pose, {100.0, 80.0}, 4.0, 30.0, 0.01);
  const Eigen::Vector3d ray = pose.C_wc * pixel_ray_c(camera, {100.0, 80.0}).normalized();
  EXPECT_TRUE(g.mean.isApprox(pose.position_w + 4.0 * ray));
  EXPECT_NEAR(ray.dot(g.covariance * ray), 900.0, 1e-9);
  const Eigen::Vector3d across = ray.cross(Eigen::Vector3d::UnitZ()).normalized();
  EXPECT_NEAR(across.dot(g.covariance * across), 1e-4, 1e-12);
}

template <typename Model>
void expect_rejections_counted(Model& model) {
  const ComparisonSetup s = fig10_setup(Motion::kForward, 8.0);
  Eigen::Vector2d pixel;
  ASSERT_TRUE(observe(Pinhole{}, s.first, s.landmark, pixel));
  EXPECT_EQ(model.update(s.second, pixel), ModelStatus::kNotInitialized);
  EXPECT_EQ(model.rejections().not_initialized, 1U);
  EXPECT_EQ(model.initialize(s.first, {kNaN, 3.0}), ModelStatus::kNonFiniteInput);
  ASSERT_EQ(model.initialize(s.first, pixel), ModelStatus::kOk);
  const Eigen::Vector3d before = model.position_w();
  EXPECT_EQ(model.update(s.second, {1.0, kNaN}), ModelStatus::kNonFiniteInput);
  KnownPose bad = s.second;
  bad.C_wc(0, 0) = kNaN;
  EXPECT_EQ(model.update(bad, pixel), ModelStatus::kNonFiniteInput);
  EXPECT_EQ(model.rejections().non_finite_input, 3U);
  KnownPose turned = s.second;
  turned.C_wc = -Eigen::Matrix3d::Identity();
  turned.C_wc(2, 2) = 1.0;  // facing backwards
  EXPECT_EQ(model.update(turned, pixel), ModelStatus::kBehindCamera);
  EXPECT_EQ(model.rejections().behind_camera, 1U);
  EXPECT_TRUE(model.position_w().isApprox(before));
  EXPECT_TRUE(model.position_w().allFinite());
}

TEST(ModelsRejection, ConventionalCountsAndIgnoresBadInput) {
  ConventionalModel model({Pinhole{}, 10.0, 1000.0, 0.005, 0.1});
  expect_rejections_counted(model);
}

TEST(ModelsRejection, InverseDepthCountsAndIgnoresBadInput) {
  InverseDepthModel model({Pinhole{}, 0.1, 0.5, 0.1, 0.1});
  expect_rejections_counted(model);
}

TEST(ModelsRejection, MultiHypothesisCountsAndIgnoresBadInput) {
  MultiHypothesisModel model({Pinhole{}, 5, 1.0, 30.0, 0.1, 1e-4});
  expect_rejections_counted(model);
}

TEST(InverseDepth, StartsOnTheRayAndConvertsToXyzOnceLinearEnough) {
  const Pinhole camera;
  InverseDepthModel model({camera, 0.1, 0.5, 0.1, 0.1});
  KnownPose pose;
  const Eigen::Vector3d landmark = landmark_w(pose, {0.2, 0.1}, 3.0);
  Eigen::Vector2d pixel;
  ASSERT_TRUE(observe(camera, pose, landmark, pixel));
  ASSERT_EQ(model.initialize(pose, pixel), ModelStatus::kOk);
  EXPECT_FALSE(model.converted_to_xyz());
  EXPECT_NEAR(model.position_w().normalized().dot(landmark.normalized()), 1.0, 1e-12);
  EXPECT_NEAR(model.position_w().norm(), 10.0, 1e-9);
  EXPECT_GT(inverse_depth_linearity_index(pose, model.inverse_depth_state(),
                                          Eigen::Matrix<double, 6, 6>::Identity() * 0.25),
            1.0);
  int updates = 0;
  while (!model.converted_to_xyz() && updates < 20) {
    pose = moved_pose(pose, Motion::kLateral, 0.3);
    ASSERT_TRUE(observe(camera, pose, landmark, pixel));
    ASSERT_EQ(model.update(pose, pixel), ModelStatus::kOk);
    ++updates;
  }
  EXPECT_TRUE(model.converted_to_xyz());
  EXPECT_LT((model.position_w() - landmark).norm(), 1e-3);
  // Updates keep working in XYZ.
  pose = moved_pose(pose, Motion::kForward, 0.3);
  ASSERT_TRUE(observe(camera, pose, landmark, pixel));
  EXPECT_EQ(model.update(pose, pixel), ModelStatus::kOk);
  EXPECT_LT((model.position_w() - landmark).norm(), 1e-3);
  const Eigen::Matrix3d P = model.covariance_w();
  EXPECT_TRUE(P.isApprox(P.transpose()));
  EXPECT_GT(cleanslam::test::min_eigenvalue(P), 0.0);
}

TEST(MultiHypothesis, LaysOutGeometricDepths) {
  const HypothesisLayout layout = hypothesis_layout(5, 1.0, 30.0);
  ASSERT_EQ(layout.count, 5U);
  EXPECT_NEAR(layout.depth[0], 1.0, 1e-12);
  EXPECT_NEAR(layout.depth[4], 30.0, 1e-9);
  const double beta = layout.depth[1] / layout.depth[0];
  for (std::size_t i = 1; i < layout.count; ++i) {
    EXPECT_NEAR(layout.depth[i] / layout.depth[i - 1], beta, 1e-9);
    EXPECT_NEAR(layout.sigma_along[i] / layout.depth[i], (beta - 1.0) / (beta + 1.0), 1e-12);
  }
  EXPECT_EQ(hypothesis_layout(1000, 1.0, 30.0).count, kMaxHypotheses);
  EXPECT_EQ(hypothesis_layout(0, 1.0, 30.0).count, 1U);
}

TEST(MultiHypothesis, PrunesUnlikelyHypothesesAndKeepsWeightsNormalized) {
  const Pinhole camera;
  MultiHypothesisModel model({camera, 10, 1.0, 30.0, 0.1, 1e-3});
  KnownPose pose;
  const Eigen::Vector3d landmark = landmark_w(pose, {0.3, 0.1}, 4.0);
  Eigen::Vector2d pixel;
  ASSERT_TRUE(observe(camera, pose, landmark, pixel));
  ASSERT_EQ(model.initialize(pose, pixel), ModelStatus::kOk);
  EXPECT_EQ(model.hypothesis_count(), 10U);
  for (int k = 0; k < 6; ++k) {
    pose = moved_pose(pose, Motion::kLateral, 0.2);
    ASSERT_TRUE(observe(camera, pose, landmark, pixel));
    ASSERT_EQ(model.update(pose, pixel), ModelStatus::kOk);
  }
  EXPECT_LT(model.hypothesis_count(), 10U);
  double total = 0.0;
  for (std::size_t i = 0; i < model.hypothesis_count(); ++i) {
    EXPECT_GE(model.weight(i), 1e-3);
    total += model.weight(i);
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_LT((model.position_w() - landmark).norm(), 0.02);
}

}  // namespace
}  // namespace cleanslam::paper_models
