#include "cleanslam/paper_models/image_plane.hpp"

namespace cleanslam::paper_models {

Eigen::Vector3d pixel_ray_c(const Pinhole& camera, const Eigen::Vector2d& pixel) {
  return {1.0, -(pixel.x() - camera.cx_px) / camera.f_px,
          -(pixel.y() - camera.cy_px) / camera.f_px};
}

bool project_c(const Pinhole& camera, const Eigen::Vector3d& p_c, Eigen::Vector2d& pixel) {
  if (!(p_c.x() > 0.0)) {
    return false;
  }
  pixel = {camera.cx_px - camera.f_px * p_c.y() / p_c.x(),
           camera.cy_px - camera.f_px * p_c.z() / p_c.x()};
  return true;
}

Eigen::Matrix<double, 2, 3> projection_jacobian_c(const Pinhole& camera,
                                                  const Eigen::Vector3d& p_c) {
  const double f = camera.f_px;
  const double inv_x = 1.0 / p_c.x();
  Eigen::Matrix<double, 2, 3> J;
  J << f * p_c.y() * inv_x * inv_x, -f * inv_x, 0.0,  //
      f * p_c.z() * inv_x * inv_x, 0.0, -f * inv_x;
  return J;
}

}  // namespace cleanslam::paper_models
