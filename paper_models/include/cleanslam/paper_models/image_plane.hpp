#pragma once

#include <Eigen/Core>

namespace cleanslam::paper_models {

// Pinhole camera of eq. 29 in the paper's camera frame c (x along the optical axis, y left, z up);
// pixels have their origin top-left, so u grows to the right and v downwards.
struct Pinhole {
  double f_px = 280.0;
  double cx_px = 160.0;
  double cy_px = 120.0;
};

// The known camera pose of the comparison scenarios: position and C_wc (camera to world).
struct KnownPose {
  Eigen::Vector3d position_w = Eigen::Vector3d::Zero();
  Eigen::Matrix3d C_wc = Eigen::Matrix3d::Identity();
};

// Ray (1, -(u-cx)/f, -(v-cy)/f) through a pixel, in c (eq. 12).
Eigen::Vector3d pixel_ray_c(const Pinhole& camera, const Eigen::Vector2d& pixel);

// Pixel of a point in c; false when the point is not in front of the camera.
bool project_c(const Pinhole& camera, const Eigen::Vector3d& p_c, Eigen::Vector2d& pixel);

// d(pixel)/d(p_c) of project_c (the left factor of eq. 32).
Eigen::Matrix<double, 2, 3> projection_jacobian_c(const Pinhole& camera,
                                                  const Eigen::Vector3d& p_c);

}  // namespace cleanslam::paper_models
