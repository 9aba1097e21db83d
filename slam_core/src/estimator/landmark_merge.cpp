#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "cleanslam/slam_core/ekf.hpp"

namespace cleanslam::slam_core {

// z = y_keep - y_drop = 0 with H = [.. I .. -I ..]: exactly linear, so the update's only error is
// in the covariance the two estimates carry. P H^T is the difference of two column blocks. With
// the kept entry considered, its rows of the gain are zero (Schmidt). The covariance follows the
// form for any gain either way.
ObservationResult Ekf::merge_landmarks(int keep, int drop, double gate_chi2, double merge_std_m) {
  finish_update();
  merge_test_ratio_ = -1.0;
  if (!valid_used_slot(keep) || !valid_used_slot(drop) || keep == drop || !(merge_std_m >= 0.0) ||
      !std::isfinite(merge_std_m)) {
    return ObservationResult::kInvalidSlot;
  }
  const int n = active_dim_;
  const int a = row_of(keep);
  const int b = row_of(drop);
  auto PHt = PHt_.topLeftCorner(n, 3);
  PHt = P_.block(0, a, n, 3) - P_.block(0, b, n, 3);
  Eigen::Matrix3d S = PHt.middleRows<3>(a) - PHt.middleRows<3>(b);
  S = (0.5 * (S + S.transpose())).eval();
  // An exact constraint conditions P on a direction S may barely span, which amplifies P's own
  // rounding by |P| / lambda_min(S) even in exact arithmetic (found by fuzzing: merge_std_m 0 of
  // two almost perfectly correlated landmarks left P indefinite). No constraint is tighter than
  // kMergeVarianceFloor of the difference's largest variance.
  constexpr double kMergeVarianceFloor = 1e-9;
  S.diagonal().array() +=
      std::max(merge_std_m * merge_std_m, kMergeVarianceFloor * S.diagonal().maxCoeff());
  const Eigen::LLT<Eigen::Matrix3d> llt(S);
  if (llt.info() != Eigen::Success) {
    return ObservationResult::kNotPositiveDefinite;
  }
  const Eigen::Vector3d nu = x_.segment<3>(b) - x_.segment<3>(a);
  merge_test_ratio_ = nu.dot(llt.solve(nu));
  if (gate_chi2 > 0.0 && !(merge_test_ratio_ <= gate_chi2)) {
    ++counters_.merges_gated;
    return ObservationResult::kGate;
  }
  const Eigen::Matrix3d Sinv = llt.solve(Eigen::Matrix3d::Identity());
  auto K = W_.topLeftCorner(n, 3);
  K.noalias() = PHt.lazyProduct(Sinv);
  if (config_.merge_considers_kept) {
    K.middleRows<3>(a).setZero();
  }
  for (int i = 0; i < n; ++i) {
    const double d = P_(i, i) - K.row(i).dot(PHt.row(i));
    if (!posterior_variance_ok(i, d)) {
      return ObservationResult::kNotPositiveDefinite;
    }
  }
  // S near singular (merge_std_m of 1e-300) can overflow the gain or the covariance's products
  // K PHt^T and K S: nothing is changed then.
  dx_.resize(n);
  dx_.noalias() = K * nu;
  const double largest_product =
      K.cwiseAbs().maxCoeff() * std::max(PHt.cwiseAbs().maxCoeff(), S.cwiseAbs().maxCoeff());
  if (!K.allFinite() || !dx_.allFinite() || !(largest_product < 1e300)) {
    dx_.resize(kMaxStateDim);
    return ObservationResult::kNotPositiveDefinite;
  }
  if (!state_in_range(n, dx_)) {
    dx_.resize(kMaxStateDim);
    return ObservationResult::kOutOfRange;
  }
  x_.head(n) += dx_;
  x_(3) = wrap_angle(x_(3));
  x_(5) = wrap_angle(x_(5));
  // P - K PHt^T - PHt K^T + K S K^T = P - K A^T - A K^T with A = PHt - K S / 2. For the optimal
  // gain too: P - K PHt^T passed K's rounding into P where S is ill-conditioned (a ray 660 m long
  // merged, found by fuzzing) and left it indefinite.
  auto A = W_.block(0, 3, n, 3);
  A = PHt;
  A.noalias() -= 0.5 * K.lazyProduct(S);
  for (int j = 0; j < n; ++j) {
    P_.col(j).segment(j, n - j).noalias() -= K.bottomRows(n - j) * A.row(j).transpose();
    P_.col(j).segment(j, n - j).noalias() -= A.bottomRows(n - j) * K.row(j).transpose();
    P_.row(j).segment(j + 1, n - j - 1) = P_.col(j).segment(j + 1, n - j - 1).transpose();
  }
  if (config_.invariant_reset) {
    begin_invariant_reset(n, dx_.head(n));
    invariant_reset_columns(0, n);
  }
  dx_.resize(kMaxStateDim);
  ++counters_.landmarks_merged;
  delete_landmark(drop);
  return ObservationResult::kFused;
}

}  // namespace cleanslam::slam_core
