#include <cmath>

#include "cleanslam/slam_core/ekf.hpp"

namespace cleanslam::slam_core {

// z = b dt - c d: H has two entries, the bias row (dt) and the drift row (-d), so P H^T is a sum
// of two columns. The update is exactly linear; it moves the pose and the map only through their
// correlations with b and c.
ObservationResult Ekf::fuse_wheel_gyro_mismatch(const OdometryIncrement::WheelGyroMismatch& m,
                                                double gate_chi2) {
  finish_update();
  mismatch_test_ratio_ = -1.0;
  if (!config_.wheel_drift_state || !config_.gyro_bias_state || m.intervals <= 0) {
    return ObservationResult::kInvalidSlot;
  }
  if (!std::isfinite(m.z) || !std::isfinite(m.dt) || !std::isfinite(m.distance) ||
      !std::isfinite(m.variance) || !(m.variance >= 0.0)) {
    counters_.rejections.add(ObservationResult::kNonFinite);
    return ObservationResult::kNonFinite;
  }
  const int n = active_dim_;
  auto PHt = PHt_.col(0).head(n);
  PHt = m.dt * P_.col(kBiasRow).head(n) - m.distance * P_.col(kDriftRow).head(n);
  const double S = m.dt * PHt(kBiasRow) - m.distance * PHt(kDriftRow) + m.variance;
  if (!(S > 0.0)) {
    return ObservationResult::kNotPositiveDefinite;
  }
  const double nu = m.z - (m.dt * x_(kBiasRow) - m.distance * x_(kDriftRow));
  mismatch_test_ratio_ = nu * nu / S;
  if (gate_chi2 > 0.0 && !(mismatch_test_ratio_ <= gate_chi2)) {
    ++counters_.wheel_gyro_mismatches_gated;
    return ObservationResult::kGate;
  }
  auto K = W_.col(0).head(n);
  K = PHt / S;
  if (config_.invariant_reset) {
    dx_.resize(n);
    dx_ = K * nu;
  }
  x_.head(n) += K * nu;
  x_(3) = wrap_angle(x_(3));
  x_(5) = wrap_angle(x_(5));
  for (int j = 0; j < n; ++j) {
    P_.col(j).segment(j, n - j) -= K.segment(j, n - j) * PHt(j);
    P_.row(j).segment(j + 1, n - j - 1) = P_.col(j).segment(j + 1, n - j - 1).transpose();
  }
  if (config_.invariant_reset) {
    begin_invariant_reset(n, dx_.head(n));
    invariant_reset_columns(0, n);
    dx_.resize(kMaxStateDim);
  }
  ++counters_.wheel_gyro_mismatches_fused;
  return ObservationResult::kFused;
}

}  // namespace cleanslam::slam_core
