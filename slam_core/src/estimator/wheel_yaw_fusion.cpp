#include "cleanslam/slam_core/wheel_yaw_fusion.hpp"

#include <algorithm>
#include <cmath>

namespace cleanslam::slam_core {

WheelYawFusion::WheelYawFusion(const WheelYawFusionConfig& config, double bias_std,
                               double bias_walk)
    : config_(config), bias_walk_(std::max(0.0, bias_walk)) {
  const double b = std::max(bias_std, 1e-6);
  P_.diagonal() << b * b, config.scale_std * config.scale_std,
      config.drift_std_rad_per_m * config.drift_std_rad_per_m;
}

bool WheelYawFusion::usable(const Reading& r) {
  return std::isfinite(r.gyro_yaw) && std::isfinite(r.gyro_var) && std::isfinite(r.wheel_yaw) &&
         std::isfinite(r.wheel_var) && std::isfinite(r.distance) && std::isfinite(r.dt) &&
         r.gyro_var >= 0.0 && r.wheel_var >= 0.0 && r.dt >= 0.0;
}

double WheelYawFusion::correlation_intervals(double dt) const {
  return dt > 0.0 ? std::max(1.0, config_.calibration_correlation_time_s / dt) : 1.0;
}

WheelYawFusion::Fused WheelYawFusion::fuse(const Reading& r) {
  silent_distance_ = 0.0;
  Fused gyro_only;
  gyro_only.yaw = r.gyro_yaw;
  gyro_only.variance = r.gyro_var;
  if (!usable(r)) {
    ++counters_.intervals_rejected;
    return gyro_only;
  }
  const double b = p_(0);
  const double s = p_(1);
  const double c = p_(2);
  const double gyro = r.gyro_yaw - b * r.dt;
  const double gyro_var = r.gyro_var + r.dt * r.dt * P_(0, 0);
  const double wheel = (1.0 + s) * r.wheel_yaw - c * r.distance;
  const Eigen::Vector2d h(r.wheel_yaw, -r.distance);
  const double wheel_noise_var = (1.0 + s) * (1.0 + s) * r.wheel_var;
  const double wheel_var = wheel_noise_var + h.dot(P_.bottomRightCorner<2, 2>() * h);
  const double total = gyro_var + wheel_var;
  if (!(total > 0.0)) {
    return gyro_only;
  }
  const double mismatch = gyro - wheel;
  if (mismatch * mismatch > config_.gate_chi2 * total) {
    ++counters_.intervals_gated;
    // A slip inside the window would bias the calibration: start the window again.
    reset_window();
    gyro_only.yaw = gyro;
    gyro_only.variance = gyro_var;
    return gyro_only;
  }
  ++counters_.intervals_fused;
  Fused out;
  out.gyro_weight = wheel_var / total;
  const double wheel_weight = 1.0 - out.gyro_weight;
  out.yaw = wheel + out.gyro_weight * mismatch;
  // The calibration's error is the same in every interval: over correlation_time_s its share of
  // the heading error adds up linearly, not as independent draws (one interval's share times the
  // number of intervals, squared, in total).
  const double intervals = correlation_intervals(r.dt);
  out.variance =
      out.gyro_weight * out.gyro_weight * r.gyro_var +
      wheel_weight * wheel_weight * (wheel_noise_var + intervals * (wheel_var - wheel_noise_var));

  sum_mismatch_ += r.gyro_yaw - r.wheel_yaw;
  sum_h_ += Eigen::Vector3d(r.dt, r.wheel_yaw, -r.distance);
  sum_gyro_var_ += r.gyro_var;
  sum_wheel_var_ += r.wheel_var;
  sum_fused_minus_gyro_ += out.yaw - gyro;
  sum_gyro_minus_fused_var_ += gyro_var - out.variance;
  ++window_count_;
  // A slip too small for one interval's gate shows in the window's sum: the window so far is
  // taken back to the gyro's heading (through this interval's output) and not learnt from.
  last_test_ratio_ = window_test_ratio();
  if (last_test_ratio_ > config_.gate_chi2) {
    ++counters_.windows_gated;
    out.yaw -= sum_fused_minus_gyro_;
    out.variance += std::max(0.0, sum_gyro_minus_fused_var_);
    out.gyro_weight = 1.0;
    reset_window();
  } else if (window_count_ >= std::max(config_.window_intervals, 1)) {
    close_window();
  }
  return out;
}

WheelYawFusion::Fused WheelYawFusion::wheels_alone(double wheel_yaw, double distance) {
  Fused out;
  out.gyro_weight = 0.0;
  out.yaw = wheel_yaw;
  if (!std::isfinite(wheel_yaw) || !std::isfinite(distance)) {
    return out;
  }
  // c and its variance given s = 0.
  double c = p_(2);
  double c_var = P_(2, 2);
  if (P_(1, 1) > 0.0) {
    c -= P_(1, 2) / P_(1, 1) * p_(1);
    c_var -= P_(1, 2) * P_(1, 2) / P_(1, 1);
  }
  const double before = silent_distance_;
  silent_distance_ += distance;
  out.yaw = wheel_yaw - c * distance;
  // Driving back shrinks the share: the variance stays at least where it was.
  out.variance =
      std::max(0.0, std::max(c_var, 0.0) * (silent_distance_ * silent_distance_ - before * before));
  return out;
}

double WheelYawFusion::window_variance(const Eigen::Vector3d& PH) const {
  const double s = p_(1);
  return sum_h_.dot(PH) + sum_gyro_var_ + (1.0 + s) * (1.0 + s) * sum_wheel_var_;
}

double WheelYawFusion::window_test_ratio() const {
  const double S = window_variance(P_ * sum_h_);
  const double nu = sum_mismatch_ - sum_h_.dot(p_);
  return S > 0.0 ? nu * nu / S : 0.0;
}

void WheelYawFusion::reset_window() {
  window_count_ = 0;
  sum_mismatch_ = 0.0;
  sum_h_.setZero();
  sum_gyro_var_ = 0.0;
  sum_wheel_var_ = 0.0;
  sum_fused_minus_gyro_ = 0.0;
  sum_gyro_minus_fused_var_ = 0.0;
}

void WheelYawFusion::close_window() {
  P_(0, 0) += bias_walk_ * bias_walk_ * sum_h_(0);
  const Eigen::Vector3d PH = P_ * sum_h_;
  const double S = window_variance(PH);
  if (S > 0.0) {
    const Eigen::Vector3d K = PH / S;
    p_ += K * (sum_mismatch_ - sum_h_.dot(p_));
    P_ -= K * PH.transpose();
    P_ = 0.5 * (P_ + P_.transpose()).eval();
    ++counters_.windows_used;
  }
  reset_window();
}

}  // namespace cleanslam::slam_core
