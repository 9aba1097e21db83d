#include "cleanslam/slam_core/camera_frame_measurement.hpp"

#include <cmath>

namespace cleanslam::slam_core {

Eigen::Vector3d point_at_depth(const Eigen::Vector3d& ct, double depth_m) {
  return depth_m * ct / ct.norm();
}

Eigen::Matrix3d ray_rotation(const Eigen::Vector3d& ct) {
  const double h2 = ct.x() * ct.x() + ct.y() * ct.y();
  const double h = std::sqrt(h2);
  const double n = std::sqrt(h2 + ct.z() * ct.z());
  double cpsi = 1.0;
  double spsi = 0.0;
  if (h > 1e-12 * n) {
    cpsi = ct.x() / h;
    spsi = ct.y() / h;
  }
  const double cphi = h / n;
  const double sphi = -ct.z() / n;
  Eigen::Matrix3d rz;
  rz << cpsi, -spsi, 0.0, spsi, cpsi, 0.0, 0.0, 0.0, 1.0;
  Eigen::Matrix3d ry;
  ry << cphi, 0.0, sphi, 0.0, 1.0, 0.0, -sphi, 0.0, cphi;
  return rz * ry;
}

double normal_noise(double depth_m, double eps_trk_px, double eps_cal_px, double focal_px) {
  return std::sqrt(eps_trk_px * eps_trk_px + eps_cal_px * eps_cal_px) * depth_m / focal_px;
}

Eigen::Matrix3d measurement_covariance(const Eigen::Vector3d& ct, double eps_ct_m,
                                       double eps_cn_m) {
  const Eigen::Matrix3d M = ray_rotation(ct);
  const Eigen::Vector3d d(eps_ct_m * eps_ct_m, eps_cn_m * eps_cn_m, eps_cn_m * eps_cn_m);
  return M * d.asDiagonal() * M.transpose();
}

Eigen::Vector3d predict_camera_point(const Vector6d& pose, const Eigen::Vector3d& y) {
  const Eigen::Matrix3d C_wc = rotation_zyx(pose(3), pose(4), pose(5));
  return C_wc.transpose() * (y - pose.head<3>());
}

void measurement_jacobian(const Vector6d& pose, const Eigen::Vector3d& y,
                          Eigen::Matrix<double, 3, 6>& H_pose, Eigen::Matrix3d& H_landmark) {
  measurement_jacobian(rotation_zyx(pose(3), pose(4), pose(5)),
                       rotation_zyx_derivatives(pose(3), pose(4), pose(5)), pose, y, H_pose,
                       H_landmark);
}

void measurement_jacobian(const Eigen::Matrix3d& C_wc, const RotationZyxDerivatives& d,
                          const Vector6d& pose, const Eigen::Vector3d& y,
                          Eigen::Matrix<double, 3, 6>& H_pose, Eigen::Matrix3d& H_landmark) {
  const Eigen::Vector3d delta = y - pose.head<3>();
  H_landmark = C_wc.transpose();
  H_pose.leftCols<3>() = -H_landmark;
  H_pose.col(3) = d.d_roll.transpose() * delta;
  H_pose.col(4) = d.d_pitch.transpose() * delta;
  H_pose.col(5) = d.d_yaw.transpose() * delta;
}

Eigen::Vector3d landmark_from_camera_point(const Vector6d& pose, const Eigen::Vector3d& v_c,
                                           Eigen::Matrix<double, 3, 6>* T_wc) {
  const Eigen::Matrix3d C_wc = rotation_zyx(pose(3), pose(4), pose(5));
  if (T_wc != nullptr) {
    const RotationZyxDerivatives d = rotation_zyx_derivatives(pose(3), pose(4), pose(5));
    T_wc->leftCols<3>().setIdentity();
    T_wc->col(3) = d.d_roll * v_c;
    T_wc->col(4) = d.d_pitch * v_c;
    T_wc->col(5) = d.d_yaw * v_c;
  }
  return pose.head<3>() + C_wc * v_c;
}

}  // namespace cleanslam::slam_core
