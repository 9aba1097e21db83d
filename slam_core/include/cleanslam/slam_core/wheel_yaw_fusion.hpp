#pragma once

#include <cstdint>

#include <Eigen/Core>

// The heading change of one encoder interval from the gyro and the wheels together. The paper
// takes the heading from the gyro alone (Section 2.3); a cheap gyro's random walk (0.05
// rad/s/sqrt(Hz) in the sparse-poor-odometry scenario) then turns the heading by tens of degrees
// between sightings, while a differential drive's wheels measure the same turn with an error that
// is mostly systematic: unequal wheel scales and a wrong wheel base.
//
// With w = (d_right - d_left) / wheel_base the wheels' heading change, d the body's distance and
// dt the interval, the true change theta is modelled as
//   theta = (1 + s) w - c d       (s: heading scale of the wheels, c: drift per metre)
//   g = theta + b dt + n_g        (the gyro, b: bias left after the dead reckoner's estimate)
// so g - w = b dt + s w - c d + n_g - (1 + s) n_w is linear in p = (b, s, c). A three-state
// Kalman filter learns p from windows of intervals: summed over a window, a turn's w stands well
// above the wheels' own noise in it, so using the noisy w as the regressor biases s little. Each
// interval's heading is the inverse-variance mean of the two corrected readings. A wheel that
// slips or spins fails the gate: a single interval at once, a smaller slip through the open
// window's sum, which then is taken back to the gyro's heading and not learnt from.
namespace cleanslam::slam_core {

struct WheelYawFusionConfig {
  bool enabled = true;        // always in the firmware; unit tests compare with the gyro's heading
  int window_intervals = 40;  // encoder intervals per calibration update (2 s at 20 Hz)
  // A window (or a single interval) whose squared mismatch exceeds gate_chi2 times its variance
  // is not fused: one wheel slipped.
  double gate_chi2 = 16.0;
  double scale_std = 0.2;            // prior std. dev. of s
  double drift_std_rad_per_m = 0.5;  // prior std. dev. of c
  // An interval's variance counts the calibration's share as if it repeated for this long (its
  // error is common to all intervals; the dead reckoner's other persistent errors are handled
  // the same way, DeadReckoningConfig::gyro_bias_correlation_time_s).
  double calibration_correlation_time_s = 50.0;
};

struct WheelYawCounters {
  std::uint64_t intervals_fused = 0;
  std::uint64_t intervals_gated = 0;     // gyro alone: the two readings disagreed beyond the gate
  std::uint64_t intervals_rejected = 0;  // non-finite or negative input: gyro alone
  std::uint64_t windows_used = 0;
  std::uint64_t windows_gated = 0;  // taken back to the gyro's heading
};

class WheelYawFusion {
 public:
  // bias_std: prior std. dev. of b (rad/s); bias_walk: its random walk (rad/s/sqrt(s)).
  WheelYawFusion(const WheelYawFusionConfig& config, double bias_std, double bias_walk);

  struct Reading {
    double gyro_yaw = 0.0;  // rad, the dead reckoner's bias already removed
    double gyro_var = 0.0;
    double wheel_yaw = 0.0;  // rad, (d_right - d_left) / wheel_base
    double wheel_var = 0.0;
    double distance = 0.0;  // m, signed
    double dt = 0.0;        // s of gyro integration
  };
  struct Fused {
    double yaw = 0.0;
    // The readings' noise, and the calibration's error as set by calibration_correlation_time_s.
    double variance = 0.0;
    double gyro_weight = 1.0;  // d yaw / d gyro_yaw
  };
  Fused fuse(const Reading& r);
  // The gyro silent: the wheels' heading change wheel_yaw over distance corrected by the drift per
  // metre learnt so far, w - c d, with c taken at s = 0: the heading scale is learnt from turns
  // alone and may still be near its prior when the gyro falls silent, so its error is left to the
  // wheels' heading noise (the caller's, with the wheels' own). The drift's error is the same
  // through the silence: its share of the heading's variance is var(c | s = 0) D^2, D the distance
  // since the gyro's last reading; the variance returned is that share's growth. fuse() ends the
  // silence.
  Fused wheels_alone(double wheel_yaw, double distance);

  // p = (b, s, c) and its covariance.
  [[nodiscard]] const Eigen::Vector3d& calibration() const { return p_; }
  [[nodiscard]] const Eigen::Matrix3d& calibration_covariance() const { return P_; }
  // The open window's squared mismatch over its variance after the last interval; -1 before.
  [[nodiscard]] double last_test_ratio() const { return last_test_ratio_; }
  [[nodiscard]] const WheelYawCounters& counters() const { return counters_; }

 private:
  // Finite, with no negative variance or time.
  [[nodiscard]] static bool usable(const Reading& r);
  // How many intervals of dt the calibration's error is counted over (its correlation time).
  [[nodiscard]] double correlation_intervals(double dt) const;
  // The open window's mismatch variance, given P_ times its regressor.
  [[nodiscard]] double window_variance(const Eigen::Vector3d& PH) const;
  [[nodiscard]] double window_test_ratio() const;
  void reset_window();
  void close_window();

  WheelYawFusionConfig config_;
  double bias_walk_;
  Eigen::Vector3d p_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d P_ = Eigen::Matrix3d::Zero();
  // Sums over the open window: g - w, the regressor (dt, w, -d), the two readings' variances.
  double sum_mismatch_ = 0.0;
  Eigen::Vector3d sum_h_ = Eigen::Vector3d::Zero();
  double sum_gyro_var_ = 0.0;
  double sum_wheel_var_ = 0.0;
  // What taking the window back to the gyro's heading undoes: the heading and the variance.
  double sum_fused_minus_gyro_ = 0.0;
  double sum_gyro_minus_fused_var_ = 0.0;
  int window_count_ = 0;
  double last_test_ratio_ = -1.0;
  double silent_distance_ = 0.0;  // m, signed, since the gyro went silent
  WheelYawCounters counters_;
};

}  // namespace cleanslam::slam_core
