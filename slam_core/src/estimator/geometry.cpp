#include "cleanslam/slam_core/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace cleanslam::slam_core {

namespace {
Eigen::Matrix3d rot_x(double a) {
  const double c = std::cos(a);
  const double s = std::sin(a);
  Eigen::Matrix3d r;
  r << 1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c;
  return r;
}
Eigen::Matrix3d rot_y(double a) {
  const double c = std::cos(a);
  const double s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c;
  return r;
}
Eigen::Matrix3d rot_z(double a) {
  const double c = std::cos(a);
  const double s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return r;
}
Eigen::Matrix3d d_rot_x(double a) {
  const double c = std::cos(a);
  const double s = std::sin(a);
  Eigen::Matrix3d r;
  r << 0.0, 0.0, 0.0, 0.0, -s, -c, 0.0, c, -s;
  return r;
}
Eigen::Matrix3d d_rot_y(double a) {
  const double c = std::cos(a);
  const double s = std::sin(a);
  Eigen::Matrix3d r;
  r << -s, 0.0, c, 0.0, 0.0, 0.0, -c, 0.0, -s;
  return r;
}
Eigen::Matrix3d d_rot_z(double a) {
  const double c = std::cos(a);
  const double s = std::sin(a);
  Eigen::Matrix3d r;
  r << -s, -c, 0.0, c, -s, 0.0, 0.0, 0.0, 0.0;
  return r;
}
}  // namespace

Eigen::Matrix3d rotation_zyx(double roll, double pitch, double yaw) {
  return rot_z(yaw) * rot_y(pitch) * rot_x(roll);
}

RotationZyxDerivatives rotation_zyx_derivatives(double roll, double pitch, double yaw) {
  const Eigen::Matrix3d rz = rot_z(yaw);
  const Eigen::Matrix3d ry = rot_y(pitch);
  const Eigen::Matrix3d rx = rot_x(roll);
  return {rz * ry * d_rot_x(roll), rz * d_rot_y(pitch) * rx, d_rot_z(yaw) * ry * rx};
}

Eigen::Matrix3d euler_rate_matrix(double roll, double pitch) {
  const double sr = std::sin(roll);
  const double cr = std::cos(roll);
  const double tp = std::tan(pitch);
  const double secp = 1.0 / std::cos(pitch);
  Eigen::Matrix3d e;
  e << 1.0, sr * tp, cr * tp, 0.0, cr, -sr, 0.0, sr * secp, cr * secp;
  return e;
}

Eigen::Matrix<double, 3, 2> euler_rate_matrix_jacobian(double roll, double pitch,
                                                       const Eigen::Vector3d& w) {
  const double sr = std::sin(roll);
  const double cr = std::cos(roll);
  const double tp = std::tan(pitch);
  const double secp = 1.0 / std::cos(pitch);
  const double sec2 = secp * secp;
  Eigen::Matrix<double, 3, 2> j;
  // Column 0: d/d roll; column 1: d/d pitch.
  j(0, 0) = cr * tp * w.y() - sr * tp * w.z();
  j(1, 0) = -sr * w.y() - cr * w.z();
  j(2, 0) = cr * secp * w.y() - sr * secp * w.z();
  j(0, 1) = sr * sec2 * w.y() + cr * sec2 * w.z();
  j(1, 1) = 0.0;
  j(2, 1) = sr * secp * tp * w.y() + cr * secp * tp * w.z();
  return j;
}

Eigen::Vector3d euler_zyx_from_rotation(const Eigen::Matrix3d& R) {
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double roll = std::atan2(R(2, 1), R(2, 2));
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  return {roll, pitch, yaw};
}

Eigen::Quaterniond quaternion_from_zyx(double roll, double pitch, double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

double wrap_angle(double a) {
  constexpr double kPi = std::numbers::pi;
  if (!std::isfinite(a)) {
    return a;
  }
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a <= 0.0) {
    a += 2.0 * kPi;
  }
  return a - kPi;
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return s;
}

}  // namespace cleanslam::slam_core
