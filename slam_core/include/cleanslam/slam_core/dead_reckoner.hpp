#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/samples.hpp"
#include "cleanslam/hal/time.hpp"
#include "cleanslam/slam_core/geometry.hpp"
#include "cleanslam/slam_core/odometry_increment.hpp"
#include "cleanslam/slam_core/wheel_yaw_fusion.hpp"

// The prediction input (Section 2.3): distance from the differential-drive encoders, heading
// change from the yaw gyro (encoders alone when the gyro is silent), turned into the increment of
// the camera pose between two camera frames (eq. 9) with its covariance Q.
namespace cleanslam::slam_core {

struct DeadReckoningConfig {
  // Travelled-distance error is a scale error within one increment, std. dev. =
  // wheels.distance_noise * distance; the gyro's angle random walk is gyro.noise_density and its
  // bias error within one increment gyro.bias_instability (both from hal::Calibration).
  // Uncertainty the dead reckoning cannot observe (held constant in the mean, eq. 3-4), per
  // square root of the distance travelled.
  double z_noise_m_per_sqrt_m = 0.003;
  double roll_pitch_noise_rad_per_sqrt_m = 0.003;
  // Heading from the encoders alone (gyro silent): random walk per square root of the wheels'
  // summed travel; large on purpose (wheel slip).
  double encoder_yaw_noise_rad_per_sqrt_m = 0.03;
  // The gyro is silent when no sample came for this long.
  double gyro_timeout_s = 0.05;
  // A tick jump needing a faster wheel than this (plus two ticks) is implausible.
  double max_wheel_speed_m_s = 1.5;
  double max_gyro_rate_rad_s = 10.0;
  // Standing still: no wheel moved more than standstill_max_ticks and |rate - bias| stayed below
  // standstill_rate_rad_s for standstill_window_s of encoder time.
  double standstill_window_s = 0.5;
  double standstill_rate_rad_s = 0.02;
  int standstill_max_ticks = 0;
  // Bias estimate: mean of the rates seen while standing still, over at most this many samples.
  int bias_max_samples = 3000;
  // take_increment() extrapolates the last wheel speed at most this far past the last encoder
  // sample (and no further back than this before it).
  double max_extrapolation_s = 0.2;
  // Encoders silent for longer while the gyro goes on (encoder outage): the distance comes from a
  // motion model, the heading from the gyro. The speed's mean is the last wheel speed (the drive
  // holds it, but may stop or change it at any moment); its error is a stationary
  // Ornstein-Uhlenbeck process with time constant outage_speed_time_constant_s (tau) and std. dev.
  // outage_speed_std_m_s (sigma_v), so the distance's variance is 2 sigma_v^2 tau^2 (x - 1 + e^-x)
  // after x = t / tau: (sigma_v t)^2 while the error persists, 2 sigma_v^2 tau per second in the
  // long run. Where the gyro's record does not cover an increment, the heading walks with rate
  // std. dev. outage_yaw_rate_std_rad_s over tau. The first encoder sample after the outage starts
  // the wheels' count again: the outage's motion is the model's.
  double outage_speed_time_constant_s = 10.0;
  double outage_speed_std_m_s = 0.1;
  double outage_yaw_rate_std_rad_s = 1.0;
  // The gyro bias persists across increments (the within-increment terms above treat it as
  // independent per increment): its std. dev. gyro.bias_instability adds bias_instability^2 * T *
  // dt to the heading variance, T this correlation time; 0 disables it.
  double gyro_bias_correlation_time_s = 10.0;
  // Relative gyro scale error, one value within an increment (like the distance scale).
  double gyro_scale_error = 0.005;
  // The heading from the gyro and the wheels together (wheel_yaw_fusion.hpp); off: the gyro's.
  WheelYawFusionConfig wheel_yaw;
};

// u = (dx_c, dpsi_c) of a body increment (dx, dy, dz, droll, dpitch, dyaw), expressed in the
// first body frame, through the extrinsic: dx_c = R_bc^T (d + R_b01 t_bc - t_bc) and
// dpsi_c = R_bc^T (droll, dpitch, dyaw) (small angles, as eq. 4 uses them); J = du / d body.
Vector6d camera_increment_from_body(const Vector6d& body, const Eigen::Matrix3d& R_body_c,
                                    const Eigen::Vector3d& t_body_c, Matrix6d* J);

struct DeadReckonerCounters {
  std::uint64_t gyro_accepted = 0;
  std::uint64_t gyro_out_of_order = 0;
  std::uint64_t gyro_duplicate = 0;
  std::uint64_t gyro_non_finite = 0;
  std::uint64_t gyro_implausible = 0;
  std::uint64_t encoder_accepted = 0;
  std::uint64_t encoder_out_of_order = 0;
  std::uint64_t encoder_duplicate = 0;
  std::uint64_t encoder_implausible = 0;
  std::uint64_t steps_without_gyro = 0;  // encoder intervals whose heading came from the wheels
  std::uint64_t increments_out_of_order = 0;
  std::uint64_t encoder_outages = 0;  // encoder samples after an outage (the count restarted)
};

class DeadReckoner {
 public:
  DeadReckoner(const hal::Calibration& calibration, const DeadReckoningConfig& config);

  // False when the sample is rejected (counted by reason).
  bool add_gyro(const hal::GyroSample& s);
  bool add_encoder(const hal::EncoderSample& s);

  // Increment of the camera pose since the previous take, interpolated to t_ns (the last wheel
  // speed and gyro rate carry it past the last sample; the next samples account for the part
  // taken ahead, so increments sum to the travelled path).
  OdometryIncrement take_increment(hal::TimeNs t_ns);

  [[nodiscard]] bool standing_still() const;
  [[nodiscard]] double gyro_bias() const { return bias_; }
  [[nodiscard]] bool gyro_silent(hal::TimeNs t_ns) const;
  // A take went past the last encoder sample by more than max_extrapolation_s: the increments
  // come from the outage's motion model until the next encoder sample.
  [[nodiscard]] bool coasting() const;

  // Planar body pose integrated at the encoder samples since start.
  [[nodiscard]] double x() const { return x_; }
  [[nodiscard]] double y() const { return y_; }
  [[nodiscard]] double yaw() const { return yaw_; }
  [[nodiscard]] hal::TimeNs last_encoder_time() const { return enc_t_; }

  [[nodiscard]] const DeadReckonerCounters& counters() const { return counters_; }
  [[nodiscard]] const WheelYawFusion& wheel_yaw_fusion() const { return wheel_yaw_; }

 private:
  // The wheels' heading calibration has been learnt from a window at least: with the gyro silent
  // it corrects the wheels' heading (before, the wheels' heading noise alone models them).
  [[nodiscard]] bool wheel_yaw_learnt() const {
    return config_.wheel_yaw.enabled && wheel_yaw_.counters().windows_used > 0;
  }
  struct Knot {
    hal::TimeNs t = 0;
    double theta = 0.0;  // integral of (rate - bias) since the first sample
    double live = 0.0;   // seconds of that integral, gaps past gyro_timeout_s left out
  };
  struct Increment {
    double x = 0.0;
    double y = 0.0;
    double yaw = 0.0;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    Eigen::Vector3d d_scale = Eigen::Vector3d::Zero();  // d(x, y, yaw) / d(distance scale error)
    Eigen::Vector3d d_bias = Eigen::Vector3d::Zero();   // d(x, y, yaw) / d(gyro bias)
    Eigen::Vector3d d_gyro_scale = Eigen::Vector3d::Zero();  // d(x, y, yaw) / d(gyro scale)
    double distance = 0.0;
    double wheel_travel = 0.0;
    bool gyro_used = true;
  };

  // Heading integral at t and the integrated time (Knot::live); false when the gyro does not cover
  // t.
  bool gyro_angle(hal::TimeNs t, double& theta, double& live) const;
  // gyro_weight: d dyaw / d (the gyro's reading), 1 without wheel_yaw fusion; distance_var:
  // variance along the track (the outage's motion model).
  void step(double distance, double dyaw, double yaw_var, double dt, bool gyro, double wheels,
            double gyro_weight, double distance_var = 0.0);
  // The wheels' counts are measured from sample s on, at rest until the next one.
  void count_from(const hal::EncoderSample& s);
  // The increment from seg_t_ to t_ns by the outage's motion model (encoder_outage.cpp).
  void coast(hal::TimeNs t_ns);
  OdometryIncrement camera_increment(const Increment& inc, double dt_s) const;

  hal::Calibration calibration_;
  DeadReckoningConfig config_;
  Eigen::Matrix3d R_body_c_;
  Eigen::Vector3d t_body_c_;

  static constexpr int kKnots = 128;
  std::array<Knot, kKnots> knots_{};
  int knot_count_ = 0;
  int knot_head_ = 0;  // index of the newest knot
  double last_rate_ = 0.0;
  hal::TimeNs gyro_series_start_ = 0;

  bool have_encoder_ = false;
  hal::TimeNs enc_t_ = 0;
  std::int32_t enc_left_ = 0;
  std::int32_t enc_right_ = 0;
  double wheel_speed_ = 0.0;
  double enc_yaw_rate_ = 0.0;

  // The increment since the last take: integrated up to seg_t_, which is past the last encoder
  // sample by pending_distance_ (and pending_yaw_ of wheel heading) when a take extrapolated.
  Increment inc_;
  hal::TimeNs seg_t_ = 0;
  hal::TimeNs last_take_t_ = 0;
  bool have_take_ = false;
  double pending_distance_ = 0.0;
  double pending_yaw_ = 0.0;
  // wheel_yaw fusion's correction of intervals that a take had already integrated from the gyro.
  double pending_fused_correction_ = 0.0;

  double x_ = 0.0;
  double y_ = 0.0;
  double yaw_ = 0.0;

  double bias_ = 0.0;
  int bias_samples_ = 0;
  hal::TimeNs last_motion_t_ = 0;
  bool have_gyro_ = false;
  hal::TimeNs gyro_t_ = 0;

  WheelYawFusion wheel_yaw_;
  DeadReckonerCounters counters_;
};

}  // namespace cleanslam::slam_core
