#include "cleanslam/slam_core/prediction_model.hpp"

namespace cleanslam::slam_core {

Vector6d predict_pose(const Vector6d& pose, const Eigen::Vector3d& dx_c,
                      const Eigen::Vector3d& dpsi_c) {
  Vector6d out = pose;
  out.head<3>() += rotation_zyx(pose(3), pose(4), pose(5)) * dx_c;  // eq. 3
  out.tail<3>() += euler_rate_matrix(pose(3), pose(4)) * dpsi_c;    // eq. 4
  return out;
}

void prediction_jacobians(const Vector6d& pose, const Eigen::Vector3d& dx_c,
                          const Eigen::Vector3d& dpsi_c, Matrix6d& F, Matrix6d& G) {
  const RotationZyxDerivatives dC = rotation_zyx_derivatives(pose(3), pose(4), pose(5));
  F.setIdentity();
  F.block<3, 1>(0, 3) = dC.d_roll * dx_c;
  F.block<3, 1>(0, 4) = dC.d_pitch * dx_c;
  F.block<3, 1>(0, 5) = dC.d_yaw * dx_c;
  F.block<3, 2>(3, 3) += euler_rate_matrix_jacobian(pose(3), pose(4), dpsi_c);
  G.setZero();
  G.topLeftCorner<3, 3>() = rotation_zyx(pose(3), pose(4), pose(5));
  G.bottomRightCorner<3, 3>() = euler_rate_matrix(pose(3), pose(4));
}

}  // namespace cleanslam::slam_core
