#pragma once

#include <Eigen/Core>

#include "cleanslam/slam_core/geometry.hpp"

// Eq. 21 is linear in the landmark and the camera position but not in the yaw. With a yaw
// uncertain by tens of degrees, the linearized covariance H P H^T of the predicted camera point
// leaves out the products of the yaw error with the landmark's and the camera's position errors
// (a yaw error turns a depth error across the ray). The truncated second-order filter (Gelb,
// "Applied Optimal Estimation", 1974, sec. 6.1) adds that part to the innovation covariance.
namespace cleanslam::slam_core {

// The Hessians of the three coordinates of h = M_cw(roll, pitch, yaw) (y - x_vp) in
// w = (y - x_vp, yaw), 4x4 each.
void camera_point_yaw_hessians(const Vector6d& camera_pose, const Eigen::Vector3d& y,
                               Eigen::Matrix4d hessians[3]);

// 1/2 [tr(H_k Q H_l Q)]_kl: the covariance of the second-order terms of h, with Q the
// covariance of w = (y - x_vp, yaw).
Eigen::Matrix3d yaw_curvature_covariance(const Vector6d& camera_pose, const Eigen::Vector3d& y,
                                         const Eigen::Matrix4d& Q);

}  // namespace cleanslam::slam_core
