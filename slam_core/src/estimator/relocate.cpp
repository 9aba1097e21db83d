#include <array>

#include <Eigen/Cholesky>

#include "cleanslam/slam_core/ekf.hpp"

namespace cleanslam::slam_core {

bool Ekf::relocate(const Vector6d& camera_pose, const Eigen::Matrix3d& planar_cov) {
  if (!camera_pose.allFinite() || !planar_cov.allFinite() || update_pending()) {
    return false;
  }
  const Eigen::Matrix3d sym = 0.5 * (planar_cov + planar_cov.transpose());
  if (Eigen::LLT<Eigen::Matrix3d>(sym).info() != Eigen::Success) {
    return false;
  }
  x_.head<6>() = camera_pose;
  x_(5) = wrap_angle(x_(5));
  constexpr std::array<Eigen::Index, 3> kPlanar{0, 1, 5};
  for (const Eigen::Index r : kPlanar) {
    P_.row(r).head(active_dim_).setZero();
    P_.col(r).head(active_dim_).setZero();
  }
  for (std::size_t i = 0; i < kPlanar.size(); ++i) {
    for (std::size_t j = 0; j < kPlanar.size(); ++j) {
      P_(kPlanar[i], kPlanar[j]) = sym(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
    }
  }
  return true;
}

}  // namespace cleanslam::slam_core
