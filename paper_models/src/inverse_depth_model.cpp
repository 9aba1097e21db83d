#include "cleanslam/paper_models/inverse_depth_model.hpp"

#include <cmath>

#include "cleanslam/paper_models/conventional_model.hpp"
#include "cleanslam/paper_models/pixel_update.hpp"

namespace cleanslam::paper_models {
namespace {

Eigen::Vector3d ray_d_azimuth(double azimuth, double elevation) {
  return {-std::cos(elevation) * std::sin(azimuth), std::cos(elevation) * std::cos(azimuth), 0.0};
}

Eigen::Vector3d ray_d_elevation(double azimuth, double elevation) {
  return {-std::sin(elevation) * std::cos(azimuth), -std::sin(elevation) * std::sin(azimuth),
          std::cos(elevation)};
}

}  // namespace

Eigen::Vector3d inverse_depth_ray_w(double azimuth, double elevation) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
          std::sin(elevation)};
}

Eigen::Vector3d inverse_depth_to_xyz(const InverseDepthState& s, Eigen::Matrix<double, 3, 6>* J) {
  const double rho = s(5);
  const Eigen::Vector3d m = inverse_depth_ray_w(s(3), s(4));
  if (J != nullptr) {
    J->leftCols<3>().setIdentity();
    J->col(3) = ray_d_azimuth(s(3), s(4)) / rho;
    J->col(4) = ray_d_elevation(s(3), s(4)) / rho;
    J->col(5) = -m / (rho * rho);
  }
  return s.head<3>() + m / rho;
}

bool inverse_depth_measurement(const Pinhole& camera, const KnownPose& pose,
                               const InverseDepthState& s, Eigen::Vector2d& h,
                               Eigen::Matrix<double, 2, 6>& H) {
  const double rho = s(5);
  const Eigen::Vector3d baseline = s.head<3>() - pose.position_w;
  const Eigen::Matrix3d C_cw = pose.C_wc.transpose();
  const Eigen::Vector3d q_c = C_cw * (rho * baseline + inverse_depth_ray_w(s(3), s(4)));
  if (!project_c(camera, q_c, h)) {
    return false;
  }
  Eigen::Matrix<double, 3, 6> dq_w;
  dq_w.leftCols<3>() = rho * Eigen::Matrix3d::Identity();
  dq_w.col(3) = ray_d_azimuth(s(3), s(4));
  dq_w.col(4) = ray_d_elevation(s(3), s(4));
  dq_w.col(5) = baseline;
  H = projection_jacobian_c(camera, q_c) * C_cw * dq_w;
  return true;
}

double inverse_depth_linearity_index(const KnownPose& pose, const InverseDepthState& s,
                                     const Eigen::Matrix<double, 6, 6>& P) {
  const double rho = s(5);
  const Eigen::Vector3d to_point = inverse_depth_to_xyz(s, nullptr) - pose.position_w;
  const double d1 = to_point.norm();
  const double cos_alpha = inverse_depth_ray_w(s(3), s(4)).dot(to_point) / d1;
  const double sigma_depth = std::sqrt(P(5, 5)) / (rho * rho);
  return 4.0 * sigma_depth / d1 * std::abs(cos_alpha);
}

ModelStatus InverseDepthModel::initialize(const KnownPose& pose, const Eigen::Vector2d& pixel) {
  if (!is_finite(pose) || !pixel.allFinite()) {
    return counted(ModelStatus::kNonFiniteInput);
  }
  const Eigen::Vector3d ray_w = pose.C_wc * pixel_ray_c(params_.camera, pixel);
  state_.head<3>() = pose.position_w;
  state_(3) = std::atan2(ray_w.y(), ray_w.x());
  state_(4) = std::atan2(ray_w.z(), std::hypot(ray_w.x(), ray_w.y()));
  state_(5) = params_.initial_inverse_depth;
  const double sigma_angle = params_.sigma_px / params_.camera.f_px;
  P_.setZero();
  P_(3, 3) = sigma_angle * sigma_angle;
  P_(4, 4) = sigma_angle * sigma_angle;
  P_(5, 5) = params_.sigma_inverse_depth * params_.sigma_inverse_depth;
  xyz_ = false;
  initialized_ = true;
  return ModelStatus::kOk;
}

ModelStatus InverseDepthModel::update(const KnownPose& pose, const Eigen::Vector2d& pixel) {
  if (!initialized_) {
    return counted(ModelStatus::kNotInitialized);
  }
  if (!is_finite(pose) || !pixel.allFinite()) {
    return counted(ModelStatus::kNonFiniteInput);
  }
  if (xyz_) {
    Eigen::Vector2d h;
    Eigen::Matrix<double, 2, 3> H;
    if (!image_plane_measurement(params_.camera, pose, y_, h, H)) {
      return counted(ModelStatus::kBehindCamera);
    }
    Eigen::Vector3d y = y_;
    Eigen::Matrix3d Py = Py_;
    const ModelStatus status = pixel_update<3>(y, Py, h, H, pixel, params_.sigma_px, nullptr);
    if (status != ModelStatus::kOk || !y.allFinite() || !Py.allFinite()) {
      return counted(status == ModelStatus::kOk ? ModelStatus::kSingularInnovation : status);
    }
    y_ = y;
    Py_ = Py;
    return ModelStatus::kOk;
  }
  Eigen::Vector2d h;
  Eigen::Matrix<double, 2, 6> H;
  if (!inverse_depth_measurement(params_.camera, pose, state_, h, H)) {
    return counted(ModelStatus::kBehindCamera);
  }
  InverseDepthState s = state_;
  Eigen::Matrix<double, 6, 6> P = P_;
  const ModelStatus status = pixel_update<6>(s, P, h, H, pixel, params_.sigma_px, nullptr);
  if (status != ModelStatus::kOk || !s.allFinite() || !P.allFinite()) {
    return counted(status == ModelStatus::kOk ? ModelStatus::kSingularInnovation : status);
  }
  state_ = s;
  P_ = P;
  if (state_(5) > 0.0 &&
      inverse_depth_linearity_index(pose, state_, P_) < params_.linearity_threshold) {
    Eigen::Matrix<double, 3, 6> J;
    y_ = inverse_depth_to_xyz(state_, &J);
    Py_ = J * P_ * J.transpose();
    xyz_ = true;
  }
  return ModelStatus::kOk;
}

Eigen::Vector3d InverseDepthModel::position_w() const {
  return xyz_ ? y_ : inverse_depth_to_xyz(state_, nullptr);
}

Eigen::Matrix3d InverseDepthModel::covariance_w() const {
  if (xyz_) {
    return Py_;
  }
  Eigen::Matrix<double, 3, 6> J;
  inverse_depth_to_xyz(state_, &J);
  return J * P_ * J.transpose();
}

}  // namespace cleanslam::paper_models
