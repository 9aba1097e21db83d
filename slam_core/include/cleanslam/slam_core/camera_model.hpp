#pragma once

#include <Eigen/Core>

#include "cleanslam/hal/calibration.hpp"

// The pinhole camera with radial-tangential distortion, and the one place where the optical frame
// of files and calibrations (z forward, x right, y down) meets the paper's camera frame c
// (x along the optical axis, y left, z up; eq. 29): x_c = z_opt, y_c = -x_opt, z_c = -y_opt.
namespace cleanslam::slam_core {

class CameraModel {
 public:
  explicit CameraModel(const hal::CameraCalibration& calibration);

  // False when the calibration has non-finite or non-positive intrinsics or a non-rigid extrinsic.
  [[nodiscard]] bool valid() const { return valid_; }

  // Distorted pixel -> normalized optical coordinates (x/z, y/z), by Gauss-Newton on the
  // radial-tangential model. False on non-finite input, outside the image, or no convergence.
  bool undistort(double u_px, double v_px, Eigen::Vector2d& normalized) const;

  // Eq. 12: direction ct = (1, -xn, -yn) in c of normalized optical coordinates.
  [[nodiscard]] static Eigen::Vector3d ray(const Eigen::Vector2d& normalized);

  // Point in c -> distorted pixel, with d(pixel)/d(p_c) when J is given. False when the point is
  // not in front of the camera or the result is not finite (the pixel may lie outside the image).
  bool project(const Eigen::Vector3d& p_c, Eigen::Vector2d& px,
               Eigen::Matrix<double, 2, 3>* J) const;

  // Distortion of normalized optical coordinates, with its 2x2 Jacobian when J is given.
  [[nodiscard]] Eigen::Vector2d distort(const Eigen::Vector2d& n, Eigen::Matrix2d* J) const;

  [[nodiscard]] bool in_image(double u_px, double v_px) const;

  // Mean focal length in pixels (f_p of eq. 16).
  [[nodiscard]] double focal_px() const { return 0.5 * (fx_ + fy_); }
  [[nodiscard]] double fx() const { return fx_; }
  [[nodiscard]] double fy() const { return fy_; }
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }

  // The camera frame c in the body frame: p_body = R_body_c * p_c + t_body_c.
  [[nodiscard]] const Eigen::Matrix3d& R_body_c() const { return R_body_c_; }
  [[nodiscard]] const Eigen::Vector3d& t_body_c() const { return t_body_c_; }

  // p_opt = R_opt_c * p_c.
  [[nodiscard]] static Eigen::Matrix3d R_opt_c();

 private:
  int width_;
  int height_;
  double fx_;
  double fy_;
  double cx_;
  double cy_;
  double k1_;
  double k2_;
  double p1_;
  double p2_;
  Eigen::Matrix3d R_body_c_;
  Eigen::Vector3d t_body_c_;
  bool valid_ = false;
};

}  // namespace cleanslam::slam_core

namespace cleanslam::slam_core {

// Poses (x, y, z, roll, pitch, yaw) of the camera frame c and of the body frame in the world,
// related by T_w_body = T_w_c * T_body_c^-1.
Eigen::Matrix<double, 6, 1> body_pose_from_camera_pose(const Eigen::Matrix<double, 6, 1>& camera,
                                                       const CameraModel& model);
Eigen::Matrix<double, 6, 1> camera_pose_from_body_pose(const Eigen::Matrix<double, 6, 1>& body,
                                                       const CameraModel& model);

}  // namespace cleanslam::slam_core
