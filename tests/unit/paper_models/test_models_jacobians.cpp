#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "cleanslam/paper_models/conventional_model.hpp"
#include "cleanslam/paper_models/image_plane.hpp"
#include "cleanslam/paper_models/inverse_depth_model.hpp"

namespace cleanslam::paper_models {
namespace {

KnownPose tilted_pose() {
  KnownPose pose;
  pose.position_w = {0.4, -0.2, 0.1};
  pose.C_wc = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
               Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitY()) *
               Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()))
                  .toRotationMatrix();
  return pose;
}

template <int N, typename F>
Eigen::Matrix<double, 2, N> numeric_jacobian(F&& h_of, const Eigen::Matrix<double, N, 1>& x) {
  Eigen::Matrix<double, 2, N> J;
  for (int i = 0; i < N; ++i) {
    const double step = 1e-6 * std::max(1.0, std::abs(x(i)));
    Eigen::Matrix<double, N, 1> plus = x;
    Eigen::Matrix<double, N, 1> minus = x;
    plus(i) += step;
    minus(i) -= step;
    J.col(i) = (h_of(plus) - h_of(minus)) / (2.0 * step);
  }
  return J;
}

TEST(ModelsImagePlane, FollowsThePixelConventionOfEq29) {
  const Pinhole camera;
  Eigen::Vector2d pixel;
  ASSERT_TRUE(project_c(camera, {10.0, 1.0, -0.5}, pixel));
  EXPECT_NEAR(pixel.x(), 160.0 - 28.0, 1e-12);  // left of the axis is left in the image
  EXPECT_NEAR(pixel.y(), 120.0 + 14.0, 1e-12);  // below the axis is down in the image
  const Eigen::Vector3d ray = pixel_ray_c(camera, pixel);
  EXPECT_NEAR(ray.y(), 0.1, 1e-12);
  EXPECT_NEAR(ray.z(), -0.05, 1e-12);
  EXPECT_FALSE(project_c(camera, {-1.0, 0.0, 0.0}, pixel));
  EXPECT_FALSE(project_c(camera, {0.0, 1.0, 0.0}, pixel));
}

TEST(ModelsJacobians, ProjectionMatchesNumericalDifferentiation) {
  const Pinhole camera;
  const Eigen::Vector3d p_c{4.0, 1.3, -0.7};
  const auto h = [&](const Eigen::Vector3d& p) {
    Eigen::Vector2d px;
    project_c(camera, p, px);
    return px;
  };
  EXPECT_TRUE(projection_jacobian_c(camera, p_c).isApprox(numeric_jacobian<3>(h, p_c), 1e-6));
}

TEST(ModelsJacobians, ConventionalMeasurementMatchesNumericalDifferentiation) {
  const Pinhole camera;
  const KnownPose pose = tilted_pose();
  const Eigen::Vector3d y{6.0, 2.5, 1.0};
  Eigen::Vector2d h;
  Eigen::Matrix<double, 2, 3> H;
  ASSERT_TRUE(image_plane_measurement(camera, pose, y, h, H));
  const auto h_of = [&](const Eigen::Vector3d& v) {
    Eigen::Vector2d out;
    Eigen::Matrix<double, 2, 3> unused;
    image_plane_measurement(camera, pose, v, out, unused);
    return out;
  };
  EXPECT_TRUE(H.isApprox(numeric_jacobian<3>(h_of, y), 1e-6));
}

TEST(ModelsJacobians, InverseDepthMeasurementMatchesNumericalDifferentiation) {
  const Pinhole camera;
  const KnownPose pose = tilted_pose();
  InverseDepthState s;
  s << 0.1, 0.2, 0.05, 0.35, 0.12, 0.15;
  Eigen::Vector2d h;
  Eigen::Matrix<double, 2, 6> H;
  ASSERT_TRUE(inverse_depth_measurement(camera, pose, s, h, H));
  const auto h_of = [&](const InverseDepthState& v) {
    Eigen::Vector2d out;
    Eigen::Matrix<double, 2, 6> unused;
    inverse_depth_measurement(camera, pose, v, out, unused);
    return out;
  };
  EXPECT_TRUE(H.isApprox(numeric_jacobian<6>(h_of, s), 1e-6));
  // The same pixel as the XYZ point the parameters encode.
  Eigen::Vector2d h_xyz;
  Eigen::Matrix<double, 2, 3> unused;
  ASSERT_TRUE(
      image_plane_measurement(camera, pose, inverse_depth_to_xyz(s, nullptr), h_xyz, unused));
  EXPECT_TRUE(h.isApprox(h_xyz, 1e-12));
}

TEST(ModelsJacobians, InverseDepthToXyzMatchesNumericalDifferentiation) {
  InverseDepthState s;
  s << 0.1, 0.2, 0.05, -0.4, 0.2, 0.08;
  Eigen::Matrix<double, 3, 6> J;
  inverse_depth_to_xyz(s, &J);
  Eigen::Matrix<double, 3, 6> numeric;
  for (int i = 0; i < 6; ++i) {
    InverseDepthState plus = s;
    InverseDepthState minus = s;
    plus(i) += 1e-7;
    minus(i) -= 1e-7;
    numeric.col(i) =
        (inverse_depth_to_xyz(plus, nullptr) - inverse_depth_to_xyz(minus, nullptr)) / 2e-7;
  }
  EXPECT_TRUE(J.isApprox(numeric, 1e-6));
}

}  // namespace
}  // namespace cleanslam::paper_models
