#include "cleanslam/slam_core/camera_model.hpp"

#include <cmath>

#include "cleanslam/slam_core/geometry.hpp"

namespace cleanslam::slam_core {

namespace {
constexpr int kUndistortIterations = 20;
constexpr double kUndistortTolerancePx = 1e-6;
constexpr double kMinOpticalDepth = 1e-6;
}  // namespace

CameraModel::CameraModel(const hal::CameraCalibration& c)
    : width_(c.width),
      height_(c.height),
      fx_(c.fx),
      fy_(c.fy),
      cx_(c.cx),
      cy_(c.cy),
      k1_(c.distortion[0]),
      k2_(c.distortion[1]),
      p1_(c.distortion[2]),
      p2_(c.distortion[3]) {
  Eigen::Matrix3d R_body_opt;
  R_body_opt << c.T_body_cam[0], c.T_body_cam[1], c.T_body_cam[2], c.T_body_cam[4], c.T_body_cam[5],
      c.T_body_cam[6], c.T_body_cam[8], c.T_body_cam[9], c.T_body_cam[10];
  t_body_c_ = Eigen::Vector3d(c.T_body_cam[3], c.T_body_cam[7], c.T_body_cam[11]);
  R_body_c_ = R_body_opt * R_opt_c();
  const bool finite = std::isfinite(fx_) && std::isfinite(fy_) && std::isfinite(cx_) &&
                      std::isfinite(cy_) && std::isfinite(k1_) && std::isfinite(k2_) &&
                      std::isfinite(p1_) && std::isfinite(p2_) && R_body_c_.allFinite() &&
                      t_body_c_.allFinite();
  // The same test as the calibration readers': a mount they accept is one the model uses.
  const bool rigid = finite && hal::camera_mount_error(c.T_body_cam) == nullptr;
  valid_ = finite && rigid && fx_ > 0.0 && fy_ > 0.0 && width_ > 0 && height_ > 0;
}

Eigen::Matrix3d CameraModel::R_opt_c() {
  Eigen::Matrix3d r;
  r << 0.0, -1.0, 0.0, 0.0, 0.0, -1.0, 1.0, 0.0, 0.0;
  return r;
}

bool CameraModel::in_image(double u_px, double v_px) const {
  return std::isfinite(u_px) && std::isfinite(v_px) && u_px >= -0.5 &&
         u_px <= static_cast<double>(width_) - 0.5 && v_px >= -0.5 &&
         v_px <= static_cast<double>(height_) - 0.5;
}

Eigen::Vector2d CameraModel::distort(const Eigen::Vector2d& n, Eigen::Matrix2d* J) const {
  const double x = n.x();
  const double y = n.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + k1_ * r2 + k2_ * r2 * r2;
  Eigen::Vector2d d(x * radial + 2.0 * p1_ * x * y + p2_ * (r2 + 2.0 * x * x),
                    y * radial + p1_ * (r2 + 2.0 * y * y) + 2.0 * p2_ * x * y);
  if (J != nullptr) {
    const double dradial_dr2 = k1_ + 2.0 * k2_ * r2;
    (*J)(0, 0) = radial + x * dradial_dr2 * 2.0 * x + 2.0 * p1_ * y + 6.0 * p2_ * x;
    (*J)(0, 1) = x * dradial_dr2 * 2.0 * y + 2.0 * p1_ * x + 2.0 * p2_ * y;
    (*J)(1, 0) = y * dradial_dr2 * 2.0 * x + 2.0 * p1_ * x + 2.0 * p2_ * y;
    (*J)(1, 1) = radial + y * dradial_dr2 * 2.0 * y + 6.0 * p1_ * y + 2.0 * p2_ * x;
  }
  return d;
}

bool CameraModel::undistort(double u_px, double v_px, Eigen::Vector2d& normalized) const {
  if (!valid_ || !in_image(u_px, v_px)) {
    return false;
  }
  const Eigen::Vector2d target((u_px - cx_) / fx_, (v_px - cy_) / fy_);
  Eigen::Vector2d n = target;
  for (int i = 0; i < kUndistortIterations; ++i) {
    Eigen::Matrix2d J;
    const Eigen::Vector2d r = distort(n, &J) - target;
    if (std::abs(r.x()) * fx_ < kUndistortTolerancePx &&
        std::abs(r.y()) * fy_ < kUndistortTolerancePx) {
      normalized = n;
      return n.allFinite();
    }
    const double det = J.determinant();
    if (!std::isfinite(det) || std::abs(det) < 1e-9) {
      return false;
    }
    n -= J.inverse() * r;
  }
  const Eigen::Vector2d r = distort(n, nullptr) - target;
  if (std::abs(r.x()) * fx_ < 1e-3 && std::abs(r.y()) * fy_ < 1e-3 && n.allFinite()) {
    normalized = n;
    return true;
  }
  return false;
}

Eigen::Vector3d CameraModel::ray(const Eigen::Vector2d& normalized) {
  return {1.0, -normalized.x(), -normalized.y()};
}

bool CameraModel::project(const Eigen::Vector3d& p_c, Eigen::Vector2d& px,
                          Eigen::Matrix<double, 2, 3>* J) const {
  if (!p_c.allFinite() || p_c.x() <= kMinOpticalDepth) {
    return false;
  }
  const Eigen::Vector3d p = R_opt_c() * p_c;
  const double iz = 1.0 / p.z();
  const Eigen::Vector2d n(p.x() * iz, p.y() * iz);
  Eigen::Matrix2d Jd;
  const Eigen::Vector2d d = distort(n, J != nullptr ? &Jd : nullptr);
  px = Eigen::Vector2d(fx_ * d.x() + cx_, fy_ * d.y() + cy_);
  if (!px.allFinite()) {
    return false;
  }
  if (J != nullptr) {
    Eigen::Matrix<double, 2, 3> dn_dp;
    dn_dp << iz, 0.0, -p.x() * iz * iz, 0.0, iz, -p.y() * iz * iz;
    const Eigen::Matrix2d F = Eigen::Vector2d(fx_, fy_).asDiagonal();
    *J = F * Jd * dn_dp * R_opt_c();
  }
  return true;
}

}  // namespace cleanslam::slam_core

namespace cleanslam::slam_core {

Eigen::Matrix<double, 6, 1> body_pose_from_camera_pose(const Eigen::Matrix<double, 6, 1>& camera,
                                                       const CameraModel& model) {
  const Eigen::Matrix3d R_wb =
      rotation_zyx(camera(3), camera(4), camera(5)) * model.R_body_c().transpose();
  Eigen::Matrix<double, 6, 1> body;
  body.head<3>() = camera.head<3>() - R_wb * model.t_body_c();
  body.tail<3>() = euler_zyx_from_rotation(R_wb);
  return body;
}

Eigen::Matrix<double, 6, 1> camera_pose_from_body_pose(const Eigen::Matrix<double, 6, 1>& body,
                                                       const CameraModel& model) {
  const Eigen::Matrix3d R_wb = rotation_zyx(body(3), body(4), body(5));
  Eigen::Matrix<double, 6, 1> camera;
  camera.head<3>() = body.head<3>() + R_wb * model.t_body_c();
  camera.tail<3>() = euler_zyx_from_rotation(R_wb * model.R_body_c());
  return camera;
}

}  // namespace cleanslam::slam_core
