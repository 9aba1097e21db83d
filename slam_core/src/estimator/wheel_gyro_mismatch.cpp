#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "cleanslam/slam_core/ekf.hpp"

namespace cleanslam::slam_core {

namespace {
constexpr double kMaxInnovationVariance = 1e10;  // in units of the measurement's own variance
}  // namespace

// The window's information about e = (b, c), A = sum h h^T / r and y = sum h z / r, is that of
// two unit-variance measurements along A's eigenvectors v: sqrt(l) v^T e = v^T y / sqrt(l). Each
// is a scalar update whose H has two entries, the bias row and the drift row, so P H^T is a sum
// of two columns. The update is exactly linear; it moves the pose and the map only through their
// correlations with b and c.
ObservationResult Ekf::fuse_wheel_gyro_mismatch(const OdometryIncrement::WheelGyroMismatch& m,
                                                double gate_chi2) {
  finish_update();
  mismatch_status_ = MismatchStatus{};
  if (!config_.wheel_drift_state || !config_.gyro_bias_state || m.intervals <= 0) {
    return ObservationResult::kInvalidSlot;
  }
  const Eigen::Matrix2d A = 0.5 * (m.information + m.information.transpose());
  if (!A.allFinite() || !m.information_vector.allFinite() || A(0, 0) < 0.0 || A(1, 1) < 0.0) {
    counters_.rejections.add(ObservationResult::kNonFinite);
    return ObservationResult::kNonFinite;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(A);
  const double largest = eig.eigenvalues()(1);
  // Sums of h h^T / r: an information with a negative eigenvalue was not made by add().
  if (!(largest > 0.0) || eig.eigenvalues()(0) < -1e-9 * largest) {
    counters_.rejections.add(ObservationResult::kNotPositiveDefinite);
    return ObservationResult::kNotPositiveDefinite;
  }
  const int n = active_dim_;
  bool fused = false;
  ObservationResult refusal = ObservationResult::kFused;
  for (int i = 1; i >= 0; --i) {
    const double l = eig.eigenvalues()(i);
    if (!(l > 1e-12 * largest)) {
      continue;
    }
    const Eigen::Vector2d h = std::sqrt(l) * eig.eigenvectors().col(i);
    const double z = eig.eigenvectors().col(i).dot(m.information_vector) / std::sqrt(l);
    auto PHt = PHt_.col(0).head(n);
    PHt = h(0) * P_.col(kBiasRow).head(n) + h(1) * P_.col(kDriftRow).head(n);
    const double S = h(0) * PHt(kBiasRow) + h(1) * PHt(kDriftRow) + 1.0;
    const double nu = z - (h(0) * x_(kBiasRow) + h(1) * x_(kDriftRow));
    const double ratio = nu * nu / S;
    ScalarFusionStatus& st =
        mismatch_status_.updates[static_cast<std::size_t>(mismatch_status_.count++)];
    st = ScalarFusionStatus{nu, S, ratio, false};
    if (gate_chi2 > 0.0 && !(ratio <= gate_chi2)) {
      continue;
    }
    auto K = W_.col(0).head(n);
    K = PHt / S;
    dx_.resize(n);
    dx_ = K * nu;
    // An information of 1e200 leaves the posterior to rounding, one of 1e300 overflows the state:
    // S beyond kMaxInnovationVariance (the windows of a run reach about 1e5), a posterior
    // variance below zero, a state beyond kMaxAbsState or a covariance product that is not
    // finite refuses the update.
    bool psd = S <= kMaxInnovationVariance && dx_.allFinite() &&
               K.cwiseAbs().maxCoeff() * PHt.cwiseAbs().maxCoeff() < 1e300;
    for (int j = 0; j < n && psd; ++j) {
      psd = P_(j, j) - K(j) * PHt(j) >= 0.0;
    }
    if (!psd || !state_in_range(n, dx_)) {
      refusal = psd ? ObservationResult::kOutOfRange : ObservationResult::kNotPositiveDefinite;
      dx_.resize(kMaxStateDim);
      continue;
    }
    st.fused = true;
    x_.head(n) += dx_;
    x_(3) = wrap_angle(x_(3));
    x_(5) = wrap_angle(x_(5));
    for (int j = 0; j < n; ++j) {
      P_.col(j).segment(j, n - j) -= K.segment(j, n - j) * PHt(j);
      P_.row(j).segment(j + 1, n - j - 1) = P_.col(j).segment(j + 1, n - j - 1).transpose();
    }
    if (config_.invariant_reset) {
      begin_invariant_reset(n, dx_.head(n));
      invariant_reset_columns(0, n);
    }
    dx_.resize(kMaxStateDim);
    fused = true;
  }
  if (!fused && refusal != ObservationResult::kFused) {
    counters_.rejections.add(refusal);
    return refusal;
  }
  if (!fused) {
    ++counters_.wheel_gyro_mismatches_gated;
    return ObservationResult::kGate;
  }
  ++counters_.wheel_gyro_mismatches_fused;
  return ObservationResult::kFused;
}

double Ekf::last_mismatch_test_ratio() const {
  double ratio = -1.0;
  for (int i = 0; i < mismatch_status_.count; ++i) {
    ratio = std::max(ratio, mismatch_status_.updates[static_cast<std::size_t>(i)].test_ratio);
  }
  return ratio;
}

}  // namespace cleanslam::slam_core
