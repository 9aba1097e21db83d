#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "cleanslam/paper_models/comparison_scenario.hpp"
#include "cleanslam/paper_models/conventional_model.hpp"
#include "cleanslam/paper_models/inverse_depth_model.hpp"
#include "cleanslam/paper_models/multi_hypothesis_model.hpp"

// Section 4.3 (Fig. 10) acceptance for the three earlier models, in metres: assumed depth 10 m,
// true range 5..15 m, 0.3 m of forward or lateral motion, one initialization and one update.
namespace cleanslam::paper_models {
namespace {

constexpr double kAssumedDepth = 10.0;

ConventionalParams conventional_params() {
  return {Pinhole{}, kAssumedDepth, 1000.0, 0.005, 0.1};
}
InverseDepthParams inverse_depth_params() {
  return {Pinhole{}, 1.0 / kAssumedDepth, 0.5, 0.1, 0.1};
}
MultiHypothesisParams multi_hypothesis_params(std::size_t n) {
  return {Pinhole{}, n, 1.0, 30.0, 0.1, 1e-4};
}

std::vector<double> ranges() {
  std::vector<double> r;
  for (int cm = 500; cm <= 1500; cm += 100) {
    r.push_back(cm / 100.0);
  }
  return r;
}

template <typename Model, typename Params>
double error_at(const Params& params, Motion motion, double range) {
  Model model(params);
  const ComparisonSetup s = fig10_setup(motion, range);
  const OneStepResult r = one_step(model, Pinhole{}, s.first, s.second, s.landmark);
  EXPECT_EQ(r.status, ModelStatus::kOk);
  return r.error;
}

class Fig10 : public ::testing::TestWithParam<Motion> {};

TEST_P(Fig10, ConventionalErrorGrowsWithTheDepthMismatch) {
  const double at_assumed =
      error_at<ConventionalModel>(conventional_params(), GetParam(), kAssumedDepth);
  EXPECT_LT(at_assumed, 1e-6);
  double previous_near = at_assumed;
  double previous_far = at_assumed;
  for (double offset = 1.0; offset <= 5.0; offset += 1.0) {
    const double near =
        error_at<ConventionalModel>(conventional_params(), GetParam(), kAssumedDepth - offset);
    const double far =
        error_at<ConventionalModel>(conventional_params(), GetParam(), kAssumedDepth + offset);
    EXPECT_GT(near, previous_near) << "range " << kAssumedDepth - offset;
    EXPECT_GT(far, previous_far) << "range " << kAssumedDepth + offset;
    previous_near = near;
    previous_far = far;
  }
  EXPECT_GT(previous_near, 1.0);  // metres: far beyond a useful estimate
  EXPECT_GT(previous_far, 1.0);
}

TEST_P(Fig10, MoreHypothesesLowerTheMultipleHypothesisError) {
  double previous = std::numeric_limits<double>::infinity();
  for (const std::size_t n : {2U, 3U, 5U, 10U, 20U}) {
    double sum = 0.0;
    for (const double range : ranges()) {
      sum += error_at<MultiHypothesisModel>(multi_hypothesis_params(n), GetParam(), range);
    }
    const double mean = sum / static_cast<double>(ranges().size());
    EXPECT_LT(mean, previous) << n << " hypotheses";
    previous = mean;
  }
  EXPECT_LT(previous, 0.15);
}

INSTANTIATE_TEST_SUITE_P(Motions, Fig10, ::testing::Values(Motion::kForward, Motion::kLateral));

TEST(Fig10InverseDepth, NearZeroForLateralMotionButNotForForwardMotion) {
  for (const double range : ranges()) {
    const double lateral =
        error_at<InverseDepthModel>(inverse_depth_params(), Motion::kLateral, range);
    EXPECT_LT(lateral, 1e-3) << "range " << range;  // below 0.1 cm
  }
  for (const double range : {5.0, 7.0, 13.0, 15.0}) {
    const double forward =
        error_at<InverseDepthModel>(inverse_depth_params(), Motion::kForward, range);
    const double lateral =
        error_at<InverseDepthModel>(inverse_depth_params(), Motion::kLateral, range);
    EXPECT_GT(forward, 0.01) << "range " << range;  // above 1 cm
    EXPECT_GT(forward, 100.0 * lateral) << "range " << range;
  }
}

TEST(Fig10Setup, PlacesTheLandmarkAtTheGivenRangeAndDirection) {
  const ComparisonSetup s = fig10_setup(Motion::kLateral, 8.0);
  EXPECT_NEAR(s.landmark.norm(), 8.0, 1e-12);
  EXPECT_NEAR(std::atan2(s.landmark.y(), s.landmark.x()), 22.0 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(std::asin(s.landmark.z() / 8.0), 15.0 * M_PI / 180.0, 1e-12);
  EXPECT_TRUE(s.second.position_w.isApprox(Eigen::Vector3d(0.0, 0.3, 0.0)));
  EXPECT_TRUE(fig10_setup(Motion::kForward, 8.0)
                  .second.position_w.isApprox(Eigen::Vector3d(0.3, 0.0, 0.0)));
}

TEST(Fig8Directions, AreReproducibleAndInsideTheirRanges) {
  const auto a = fig8_directions(7);
  const auto b = fig8_directions(7);
  const auto c = fig8_directions(8);
  bool differs = false;
  for (std::size_t i = 0; i < kFig8Landmarks; ++i) {
    EXPECT_EQ(a[i].azimuth, b[i].azimuth);
    EXPECT_LE(std::abs(a[i].azimuth), 25.0 * M_PI / 180.0);
    EXPECT_LE(std::abs(a[i].elevation), 15.0 * M_PI / 180.0);
    differs = differs || a[i].azimuth != c[i].azimuth;
  }
  EXPECT_TRUE(differs);
}

}  // namespace
}  // namespace cleanslam::paper_models
