#pragma once

#include <Eigen/Core>

#include "cleanslam/paper_models/image_plane.hpp"

namespace cleanslam::paper_models {

struct Gaussian3 {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// A point on the pixel's ray at an assumed depth, with standard deviation sigma_along along the
// ray and sigma_across across it, in the world (eq. 12-14, 17 and 39-40 with a known pose).
Gaussian3 ray_gaussian_w(const Pinhole& camera, const KnownPose& pose, const Eigen::Vector2d& pixel,
                         double depth, double sigma_along, double sigma_across);

}  // namespace cleanslam::paper_models
