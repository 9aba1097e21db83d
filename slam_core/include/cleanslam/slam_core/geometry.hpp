#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

// Rotations of the paper's Euler ZYX convention: C_wc = Rz(yaw) Ry(pitch) Rx(roll).
namespace cleanslam::slam_core {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// C_wc (camera to world) of the Euler angles.
Eigen::Matrix3d rotation_zyx(double roll, double pitch, double yaw);

// Partial derivatives of rotation_zyx with respect to roll, pitch and yaw (eq. 23, 42).
struct RotationZyxDerivatives {
  Eigen::Matrix3d d_roll;
  Eigen::Matrix3d d_pitch;
  Eigen::Matrix3d d_yaw;
};
RotationZyxDerivatives rotation_zyx_derivatives(double roll, double pitch, double yaw);

// Eq. 4: the matrix E with d(roll, pitch, yaw) = E(roll, pitch) * omega_c (body rates in c).
Eigen::Matrix3d euler_rate_matrix(double roll, double pitch);
// d(E * w)/d(roll) and d(E * w)/d(pitch) as columns of a 3x2 matrix.
Eigen::Matrix<double, 3, 2> euler_rate_matrix_jacobian(double roll, double pitch,
                                                       const Eigen::Vector3d& w);

// Euler ZYX angles (roll, pitch, yaw) of a rotation matrix; pitch in [-pi/2, pi/2].
Eigen::Vector3d euler_zyx_from_rotation(const Eigen::Matrix3d& R);

Eigen::Quaterniond quaternion_from_zyx(double roll, double pitch, double yaw);

// Angle wrapped to (-pi, pi].
double wrap_angle(double a);

Eigen::Matrix3d skew(const Eigen::Vector3d& v);

}  // namespace cleanslam::slam_core
