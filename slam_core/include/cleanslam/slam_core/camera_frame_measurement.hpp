#pragma once

#include <Eigen/Core>

#include "cleanslam/slam_core/geometry.hpp"

// The paper's measurement in the camera frame (eq. 12-24) and the landmark it initializes
// (eq. 39-42), as free functions shared by the EKF and the comparison models. A camera pose is
// (x, y, z, roll, pitch, yaw) of the frame c in the world.
namespace cleanslam::slam_core {

// Eq. 13: v_c = d * ct / |ct|.
Eigen::Vector3d point_at_depth(const Eigen::Vector3d& ct, double depth_m);

// Eq. 18-20: M_ct, the rotation that turns the x axis onto ct. A ray along +-z (no horizontal
// component) takes psi_ct = 0.
Eigen::Matrix3d ray_rotation(const Eigen::Vector3d& ct);

// Eq. 16: eps_cn = sqrt(eps_trk^2 + eps_cal^2) * d / f_p.
double normal_noise(double depth_m, double eps_trk_px, double eps_cal_px, double focal_px);

// Eq. 14, 17: R_v = M_ct diag(eps_ct^2, eps_cn^2, eps_cn^2) M_ct^T.
Eigen::Matrix3d measurement_covariance(const Eigen::Vector3d& ct, double eps_ct_m, double eps_cn_m);

// Eq. 21: h_j = M_cw (y_j - x_vp).
Eigen::Vector3d predict_camera_point(const Vector6d& camera_pose, const Eigen::Vector3d& y);

// Eq. 22-24: H_j = [-M_cw | dM_cw,j | M_cw], split into the pose (3x6) and landmark (3x3) parts.
void measurement_jacobian(const Vector6d& camera_pose, const Eigen::Vector3d& y,
                          Eigen::Matrix<double, 3, 6>& H_pose, Eigen::Matrix3d& H_landmark);
// The same with the pose's M_wc and its derivatives given (several landmarks seen from one pose).
void measurement_jacobian(const Eigen::Matrix3d& C_wc, const RotationZyxDerivatives& dC_wc,
                          const Vector6d& camera_pose, const Eigen::Vector3d& y,
                          Eigen::Matrix<double, 3, 6>& H_pose, Eigen::Matrix3d& H_landmark);

// Eq. 39: y = x_vp + M_wc v_c; with T_wc = [I | dM_wc] of eq. 41-42 (d y / d pose) when given.
Eigen::Vector3d landmark_from_camera_point(const Vector6d& camera_pose, const Eigen::Vector3d& v_c,
                                           Eigen::Matrix<double, 3, 6>* T_wc);

}  // namespace cleanslam::slam_core
