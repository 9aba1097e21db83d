#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "cleanslam/slam_core/frontend/search_region.hpp"
#include "symmetric_eigen.hpp"

namespace fe = cleanslam::slam_core::frontend;

namespace {
fe::PixelPrediction prediction(double u, double v, double sxx, double sxy, double syy) {
  fe::PixelPrediction p;
  p.uv = {u, v};
  p.S << sxx, sxy, sxy, syy;
  p.depth_m = 2.0;
  p.in_front = true;
  return p;
}
}  // namespace

TEST(FrontendSearchRegion, BoundingBoxOfTheGatedEllipse) {
  const fe::SearchRegion r = fe::make_search_region(prediction(160, 120, 16.0, 5.0, 4.0), 320, 240);
  ASSERT_TRUE(r.valid);
  EXPECT_NEAR(r.x_max - 160.0, std::sqrt(9.21 * 16.0), 1e-12);
  EXPECT_NEAR(120.0 - r.y_min, std::sqrt(9.21 * 4.0), 1e-12);
  // Points on the gate's boundary along each axis of the ellipse.
  Eigen::Matrix2d S;
  S << 16.0, 5.0, 5.0, 4.0;
  const auto es = cleanslam::test::symmetric_eigen(S);
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector2d d = es.vectors.col(i) * std::sqrt(9.21 * es.values(i));
    EXPECT_TRUE(r.contains(160 + 0.99 * d.x(), 120 + 0.99 * d.y()));
    EXPECT_FALSE(r.contains(160 + 1.01 * d.x(), 120 + 1.01 * d.y()));
    EXPECT_NEAR(r.mahalanobis2(160 + d.x(), 120 + d.y()), 9.21, 1e-9);
  }
}

TEST(FrontendSearchRegion, ClippedToWherePatchesFitAndBounded) {
  const fe::SearchRegion r = fe::make_search_region(prediction(5, 230, 1e4, 0.0, 1e4), 320, 240);
  ASSERT_TRUE(r.valid);
  EXPECT_DOUBLE_EQ(r.x_min, 8.0);
  EXPECT_DOUBLE_EQ(r.y_max, 231.0);
  EXPECT_DOUBLE_EQ(r.x_max, 5.0 + 40.0);
  EXPECT_DOUBLE_EQ(r.y_min, 230.0 - 40.0);
  EXPECT_FALSE(r.contains(4.0, 230.0));
}

TEST(FrontendSearchRegion, NoSearchOutsideTheImage) {
  const fe::SearchRegion r = fe::make_search_region(prediction(-50, 120, 4.0, 0.0, 4.0), 320, 240);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.failure, fe::RegionFailure::kOutsideImage);
  EXPECT_FALSE(r.contains(-50, 120));
}

TEST(FrontendSearchRegion, RejectsBehindCameraNonFiniteAndIndefinite) {
  fe::PixelPrediction behind = prediction(160, 120, 4.0, 0.0, 4.0);
  behind.in_front = false;
  EXPECT_EQ(fe::make_search_region(behind, 320, 240).failure, fe::RegionFailure::kNotInFront);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(fe::make_search_region(prediction(nan, 120, 4.0, 0.0, 4.0), 320, 240).failure,
            fe::RegionFailure::kNonFinite);
  EXPECT_EQ(fe::make_search_region(prediction(160, 120, 4.0, nan, 4.0), 320, 240).failure,
            fe::RegionFailure::kNonFinite);
  EXPECT_EQ(fe::make_search_region(prediction(160, 120, 4.0, 5.0, 4.0), 320, 240).failure,
            fe::RegionFailure::kNotPositiveDefinite);
  EXPECT_EQ(fe::make_search_region(prediction(160, 120, -1.0, 0.0, 4.0), 320, 240).failure,
            fe::RegionFailure::kNotPositiveDefinite);
}
