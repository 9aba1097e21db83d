#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include <Eigen/Geometry>

#include "cleanslam/paper_models/comparison_scenario.hpp"
#include "cleanslam/paper_models/proposed_model.hpp"
#include "cleanslam/slam_core/ekf.hpp"

// The paper's model through the real Ekf, with the pose known exactly (Sections 4.1 and 4.3).
namespace cleanslam::paper_models {
namespace {

std::unique_ptr<slam_core::Ekf> make_ekf(const ProposedParams& params) {
  return std::make_unique<slam_core::Ekf>(pinhole_calibration(params.camera),
                                          proposed_config(params));
}

std::array<Eigen::Vector3d, kFig8Landmarks> fig8_landmarks() {
  std::array<Eigen::Vector3d, kFig8Landmarks> landmarks{};
  const auto directions = fig8_directions(2012);
  for (std::size_t i = 0; i < kFig8Landmarks; ++i) {
    landmarks[i] = landmark_w(KnownPose{}, directions[i], 10.0);
  }
  return landmarks;
}

class ProposedFig10 : public ::testing::TestWithParam<Motion> {};

TEST_P(ProposedFig10, ErrorStaysBelowATenthOfAMillimetreOverTheSweep) {
  const ProposedParams params{Pinhole{}, 1000.0, 0.005, 10.0, 1e12};
  const auto ekf = make_ekf(params);
  for (int cm = 500; cm <= 1500; cm += 100) {
    const ComparisonSetup s = fig10_setup(GetParam(), cm / 100.0);
    ProposedModel model(*ekf);
    const OneStepResult r = one_step(model, Pinhole{}, s.first, s.second, s.landmark);
    ASSERT_EQ(r.status, ModelStatus::kOk) << "range " << cm << " cm";
    EXPECT_LT(r.error, 1e-4) << "range " << cm << " cm";  // 0.01 cm
  }
}

INSTANTIATE_TEST_SUITE_P(Motions, ProposedFig10,
                         ::testing::Values(Motion::kForward, Motion::kLateral));

// The forward motion of Fig. 10 at 8 m, its first pixel, and the model on a fresh filter.
class ProposedModelTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(observe(Pinhole{}, s.first, s.landmark, pixel)); }
  std::unique_ptr<slam_core::Ekf> ekf =
      make_ekf(ProposedParams{Pinhole{}, 1000.0, 0.005, 10.0, 1e12});
  ProposedModel model{*ekf};
  ComparisonSetup s = fig10_setup(Motion::kForward, 8.0);
  Eigen::Vector2d pixel;
};

TEST_F(ProposedModelTest, RejectsBadInputAndRotations) {
  EXPECT_EQ(model.update(s.second, pixel), ModelStatus::kNotInitialized);
  ASSERT_EQ(model.initialize(s.first, pixel), ModelStatus::kOk);
  EXPECT_NEAR((model.position_w() - s.first.position_w).norm(), 10.0, 1e-9);
  EXPECT_EQ(model.update(s.second, {std::numeric_limits<double>::quiet_NaN(), 1.0}),
            ModelStatus::kNonFiniteInput);
  KnownPose rotated = s.second;
  rotated.C_wc = Eigen::Matrix3d(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()));
  EXPECT_EQ(model.update(rotated, pixel), ModelStatus::kUnsupportedMotion);
  EXPECT_EQ(model.rejections().not_initialized, 1U);
  EXPECT_EQ(model.rejections().non_finite_input, 1U);
  EXPECT_EQ(model.rejections().unsupported_motion, 1U);
}

// A pose the filter cannot represent (2000 km away) is refused by Ekf::reset: the landmark must
// not be placed from the filter's previous pose instead.
TEST_F(ProposedModelTest, APoseTheFilterRefusesInitializesNothing) {
  ASSERT_EQ(model.initialize(s.first, pixel), ModelStatus::kOk);
  KnownPose far = s.first;
  far.position_w.x() = 2.0 * slam_core::Ekf::kMaxAbsState;
  EXPECT_EQ(model.initialize(far, pixel), ModelStatus::kRejectedByFilter);
  EXPECT_EQ(model.update(s.second, pixel), ModelStatus::kNotInitialized);
  EXPECT_EQ(model.rejections().rejected_by_filter, 1U);
}

TEST(ProposedFig8, ZeroErrorAtZeroDepthDifference) {
  const KnownPose first;
  const KnownPose second = moved_pose(first, Motion::kForward, 0.15);
  for (const double ect : {2.0, 10.0, 1000.0}) {
    const auto ekf = make_ekf({Pinhole{}, ect, 0.005, 10.0, 1e12});
    const BatchResult r = proposed_one_step_batch(*ekf, Pinhole{}, first, second, fig8_landmarks());
    EXPECT_EQ(r.fused, static_cast<int>(kFig8Landmarks));
    EXPECT_LT(r.rms, 1e-9) << "eps_ct " << ect << " m";
  }
}

TEST(ProposedFig8, ErrorFallsAsEpsCtGrows) {
  const KnownPose first;
  const KnownPose second = moved_pose(first, Motion::kForward, 0.15);
  for (const double diff : {10.0, 20.0, 30.0}) {
    double previous = std::numeric_limits<double>::infinity();
    for (const double ect : {2.0, 10.0, 30.0, 100.0, 1000.0}) {
      const auto ekf = make_ekf({Pinhole{}, ect, 0.005, 10.0 + diff, 1e12});
      const BatchResult r =
          proposed_one_step_batch(*ekf, Pinhole{}, first, second, fig8_landmarks());
      ASSERT_EQ(r.fused, static_cast<int>(kFig8Landmarks));
      EXPECT_LT(r.rms, previous) << "eps_ct " << ect << " m, depth difference " << diff << " m";
      previous = r.rms;
    }
    EXPECT_LT(previous, 0.01) << "depth difference " << diff << " m";
  }
}

}  // namespace
}  // namespace cleanslam::paper_models
