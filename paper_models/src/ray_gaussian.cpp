#include "cleanslam/paper_models/ray_gaussian.hpp"

namespace cleanslam::paper_models {

Gaussian3 ray_gaussian_w(const Pinhole& camera, const KnownPose& pose, const Eigen::Vector2d& pixel,
                         double depth, double sigma_along, double sigma_across) {
  const Eigen::Vector3d ray_w = pose.C_wc * pixel_ray_c(camera, pixel).normalized();
  const Eigen::Matrix3d along = ray_w * ray_w.transpose();
  Gaussian3 g;
  g.mean = pose.position_w + depth * ray_w;
  g.covariance = sigma_along * sigma_along * along +
                 sigma_across * sigma_across * (Eigen::Matrix3d::Identity() - along);
  return g;
}

}  // namespace cleanslam::paper_models
