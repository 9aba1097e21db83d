#include "cleanslam/paper_models/conventional_model.hpp"

#include "cleanslam/paper_models/pixel_update.hpp"

namespace cleanslam::paper_models {

bool image_plane_measurement(const Pinhole& camera, const KnownPose& pose,
                             const Eigen::Vector3d& y_w, Eigen::Vector2d& h,
                             Eigen::Matrix<double, 2, 3>& H) {
  const Eigen::Matrix3d C_cw = pose.C_wc.transpose();
  const Eigen::Vector3d p_c = C_cw * (y_w - pose.position_w);
  if (!project_c(camera, p_c, h)) {
    return false;
  }
  H = projection_jacobian_c(camera, p_c) * C_cw;
  return true;
}

ModelStatus ConventionalModel::initialize(const KnownPose& pose, const Eigen::Vector2d& pixel) {
  if (!is_finite(pose) || !pixel.allFinite()) {
    return counted(ModelStatus::kNonFiniteInput);
  }
  state_ = ray_gaussian_w(params_.camera, pose, pixel, params_.assumed_depth, params_.sigma_along,
                          params_.sigma_across);
  initialized_ = true;
  return ModelStatus::kOk;
}

ModelStatus ConventionalModel::update(const KnownPose& pose, const Eigen::Vector2d& pixel) {
  if (!initialized_) {
    return counted(ModelStatus::kNotInitialized);
  }
  if (!is_finite(pose) || !pixel.allFinite()) {
    return counted(ModelStatus::kNonFiniteInput);
  }
  Eigen::Vector2d h;
  Eigen::Matrix<double, 2, 3> H;
  if (!image_plane_measurement(params_.camera, pose, state_.mean, h, H)) {
    return counted(ModelStatus::kBehindCamera);
  }
  Gaussian3 next = state_;
  const ModelStatus status =
      pixel_update<3>(next.mean, next.covariance, h, H, pixel, params_.sigma_px, nullptr);
  if (status != ModelStatus::kOk) {
    return counted(status);
  }
  if (!next.mean.allFinite() || !next.covariance.allFinite()) {
    return counted(ModelStatus::kSingularInnovation);
  }
  state_ = next;
  return ModelStatus::kOk;
}

}  // namespace cleanslam::paper_models
