#include "cleanslam/slam_core/yaw_curvature.hpp"

namespace cleanslam::slam_core {

void camera_point_yaw_hessians(const Vector6d& camera_pose, const Eigen::Vector3d& y,
                               Eigen::Matrix4d hessians[3]) {
  const double roll = camera_pose(3);
  const double pitch = camera_pose(4);
  const double yaw = camera_pose(5);
  const Eigen::Matrix3d M_wc = rotation_zyx(roll, pitch, yaw);
  const Eigen::Matrix3d dM_wc = rotation_zyx_derivatives(roll, pitch, yaw).d_yaw;
  // d^2 Rz / d yaw^2 = -Rz with its z row zeroed, so d^2 M_wc / d yaw^2 = -(I - e_z e_z^T) M_wc.
  Eigen::Matrix3d d2M_wc = -M_wc;
  d2M_wc.row(2).setZero();
  const Eigen::Vector3d u = y - camera_pose.head<3>();
  for (int k = 0; k < 3; ++k) {
    // h_k = M_wc.col(k) . u
    Eigen::Matrix4d& H = hessians[k];
    H.setZero();
    H.block<3, 1>(0, 3) = dM_wc.col(k);
    H.block<1, 3>(3, 0) = dM_wc.col(k).transpose();
    H(3, 3) = d2M_wc.col(k).dot(u);
  }
}

Eigen::Matrix3d yaw_curvature_covariance(const Vector6d& camera_pose, const Eigen::Vector3d& y,
                                         const Eigen::Matrix4d& Q) {
  Eigen::Matrix4d H[3];
  camera_point_yaw_hessians(camera_pose, y, H);
  Eigen::Matrix4d HQ[3];
  for (int k = 0; k < 3; ++k) {
    HQ[k].noalias() = H[k] * Q;
  }
  Eigen::Matrix3d C;
  for (int k = 0; k < 3; ++k) {
    for (int l = k; l < 3; ++l) {
      C(k, l) = 0.5 * (HQ[k] * HQ[l]).trace();
      C(l, k) = C(k, l);
    }
  }
  return C;
}

}  // namespace cleanslam::slam_core
