#pragma once

#include <Eigen/Core>

#include "cleanslam/slam_core/geometry.hpp"

// Eq. 3-4: the camera pose moved by a dead-reckoning increment u = (dx_c, dpsi_c) of eq. 9.
namespace cleanslam::slam_core {

Vector6d predict_pose(const Vector6d& camera_pose, const Eigen::Vector3d& dx_c,
                      const Eigen::Vector3d& dpsi_c);

// F = d f / d x_v and G = d f / d u of eq. 7-8 (angles not wrapped).
void prediction_jacobians(const Vector6d& camera_pose, const Eigen::Vector3d& dx_c,
                          const Eigen::Vector3d& dpsi_c, Matrix6d& F, Matrix6d& G);

}  // namespace cleanslam::slam_core
