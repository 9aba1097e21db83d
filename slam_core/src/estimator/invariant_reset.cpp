#include "cleanslam/slam_core/ekf.hpp"

// The invariant EKF's reset (Barrau and Bonnabel, "An EKF-SLAM algorithm with consistency
// properties", 2015), written in the world-centric coordinates of eq. 1-2. A rotation by a small
// angle a about the world's vertical moves the yaw by a and every position q (the camera's, each
// landmark's) by a e_z x q; no measurement changes under it. The invariant EKF keeps its error in
// coordinates where that rotation does not depend on the estimate, so moving the estimate from x-
// to x+ maps the covariance by M = T(x+) T(x-)^-1 = I + v e_yaw^T with v = e_z x (x+ - x-) in each
// position block.
namespace cleanslam::slam_core {

namespace {
constexpr int kYawRow = 5;
}  // namespace

void Ekf::begin_invariant_reset(int n, const Eigen::Ref<const Eigen::VectorXd>& dx) {
  reset_v_.setZero(n);
  reset_v_(0) = -dx(1);
  reset_v_(1) = dx(0);
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    const int r = row_of(s);
    if (r + 2 >= n) {
      break;
    }
    if (used_[static_cast<std::size_t>(s)]) {
      reset_v_(r) = -dx(r + 1);
      reset_v_(r + 1) = dx(r);
    }
  }
  reset_yaw_col_ = P_.col(kYawRow).head(n);
  reset_yaw_var_ = P_(kYawRow, kYawRow);
}

// (M P M^T)_ij = P_ij + v_i p_j + p_i v_j + P_yaw,yaw v_i v_j, p = P's yaw column before the reset.
void Ekf::invariant_reset_columns(int begin, int end) {
  const int n = static_cast<int>(reset_v_.size());
  for (int j = begin; j < end; ++j) {
    const double vj = reset_v_(j);
    const double pj = reset_yaw_col_(j) + reset_yaw_var_ * vj;
    auto col = P_.col(j).segment(j, n - j);
    col += pj * reset_v_.segment(j, n - j) + vj * reset_yaw_col_.segment(j, n - j);
    P_.row(j).segment(j + 1, n - j - 1) = P_.col(j).segment(j + 1, n - j - 1).transpose();
  }
}

}  // namespace cleanslam::slam_core
