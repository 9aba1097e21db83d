#include "cleanslam/slam_core/dead_reckoner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "cleanslam/slam_core/camera_model.hpp"
#include "cleanslam/slam_core/geometry.hpp"

namespace cleanslam::slam_core {

namespace {
double seconds(hal::TimeNs dt) {
  return hal::to_seconds(dt);
}
}  // namespace

Vector6d camera_increment_from_body(const Vector6d& body, const Eigen::Matrix3d& R_body_c,
                                    const Eigen::Vector3d& t_body_c, Matrix6d* J) {
  // T_c0c1 = T_bc^-1 T_b0b1 T_bc.
  const Eigen::Matrix3d Rcb = R_body_c.transpose();
  const Eigen::Matrix3d R = rotation_zyx(body(3), body(4), body(5));
  Vector6d u;
  u.head<3>() = Rcb * (body.head<3>() + R * t_body_c - t_body_c);
  u.tail<3>() = Rcb * body.tail<3>();
  if (J != nullptr) {
    const RotationZyxDerivatives dR = rotation_zyx_derivatives(body(3), body(4), body(5));
    J->setZero();
    J->topLeftCorner<3, 3>() = Rcb;
    J->block<3, 1>(0, 3) = Rcb * dR.d_roll * t_body_c;
    J->block<3, 1>(0, 4) = Rcb * dR.d_pitch * t_body_c;
    J->block<3, 1>(0, 5) = Rcb * dR.d_yaw * t_body_c;
    J->bottomRightCorner<3, 3>() = Rcb;
  }
  return u;
}

DeadReckoner::DeadReckoner(const hal::Calibration& calibration, const DeadReckoningConfig& config)
    : calibration_(calibration),
      config_(config),
      wheel_yaw_(config.wheel_yaw, calibration.gyro.bias_instability, calibration.gyro.bias_walk) {
  const CameraModel camera(calibration.camera);
  R_body_c_ = camera.R_body_c();
  t_body_c_ = camera.t_body_c();
}

bool DeadReckoner::gyro_angle(hal::TimeNs t, double& theta, double& live) const {
  if (knot_count_ == 0 || t < gyro_series_start_) {
    return false;
  }
  const Knot& newest = knots_[static_cast<std::size_t>(knot_head_)];
  const auto timeout = hal::from_seconds(config_.gyro_timeout_s);
  if (t >= newest.t) {
    if (t - newest.t > timeout) {
      return false;
    }
    const double ahead = seconds(t - newest.t);
    theta = newest.theta + (last_rate_ - bias_) * ahead;
    live = newest.live + ahead;
    return true;
  }
  for (int i = 1; i < knot_count_; ++i) {
    const Knot& older = knots_[static_cast<std::size_t>((knot_head_ - i + kKnots) % kKnots)];
    if (older.t <= t) {
      const Knot& newer = knots_[static_cast<std::size_t>((knot_head_ - i + 1 + kKnots) % kKnots)];
      const double f = seconds(t - older.t) / seconds(newer.t - older.t);
      theta = older.theta + f * (newer.theta - older.theta);
      live = older.live + f * (newer.live - older.live);
      return true;
    }
  }
  return false;
}

bool DeadReckoner::gyro_silent(hal::TimeNs t_ns) const {
  return !have_gyro_ || t_ns - gyro_t_ > hal::from_seconds(config_.gyro_timeout_s);
}

bool DeadReckoner::add_gyro(const hal::GyroSample& s) {
  if (!std::isfinite(s.wz_rad_s) ||
      (s.has_xy && (!std::isfinite(s.wx_rad_s) || !std::isfinite(s.wy_rad_s)))) {
    ++counters_.gyro_non_finite;
    return false;
  }
  if (std::abs(s.wz_rad_s) > config_.max_gyro_rate_rad_s) {
    ++counters_.gyro_implausible;
    return false;
  }
  if (have_gyro_ && s.t_ns < gyro_t_) {
    ++counters_.gyro_out_of_order;
    return false;
  }
  if (have_gyro_ && s.t_ns == gyro_t_) {
    ++counters_.gyro_duplicate;
    return false;
  }
  double theta = 0.0;
  double live = 0.0;
  const bool continues =
      have_gyro_ && s.t_ns - gyro_t_ <= hal::from_seconds(config_.gyro_timeout_s);
  if (knot_count_ > 0) {
    theta = knots_[static_cast<std::size_t>(knot_head_)].theta;
    live = knots_[static_cast<std::size_t>(knot_head_)].live;
  }
  if (continues) {
    theta += 0.5 * ((last_rate_ - bias_) + (s.wz_rad_s - bias_)) * seconds(s.t_ns - gyro_t_);
    live += seconds(s.t_ns - gyro_t_);
  } else if (!continues) {
    gyro_series_start_ = s.t_ns;
  }
  knot_head_ = (knot_head_ + 1) % kKnots;
  knots_[static_cast<std::size_t>(knot_head_)] = Knot{s.t_ns, theta, live};
  knot_count_ = std::min(knot_count_ + 1, kKnots);
  last_rate_ = s.wz_rad_s;
  gyro_t_ = s.t_ns;
  have_gyro_ = true;
  ++counters_.gyro_accepted;

  if (std::abs(s.wz_rad_s - bias_) > config_.standstill_rate_rad_s) {
    last_motion_t_ = std::max(last_motion_t_, s.t_ns);
  } else if (standing_still()) {
    bias_samples_ = std::min(bias_samples_ + 1, std::max(config_.bias_max_samples, 1));
    bias_ += (s.wz_rad_s - bias_) / static_cast<double>(bias_samples_);
  }
  return true;
}

bool DeadReckoner::standing_still() const {
  return have_encoder_ && !coasting() &&
         seconds(enc_t_ - last_motion_t_) >= config_.standstill_window_s;
}

void DeadReckoner::step(double distance, double dyaw, double yaw_var, double dt, bool gyro,
                        double wheels, double gyro_weight, double distance_var) {
  Increment& in = inc_;
  const double mid = in.yaw + 0.5 * dyaw;
  const double c = std::cos(mid);
  const double s = std::sin(mid);
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 2) = -distance * s;
  F(1, 2) = distance * c;
  const Eigen::Vector3d g_yaw(-0.5 * distance * s, 0.5 * distance * c, 1.0);
  if (gyro) {
    const double bi = calibration_.gyro.bias_instability;
    yaw_var +=
        gyro_weight * gyro_weight * bi * bi * config_.gyro_bias_correlation_time_s * std::abs(dt);
  }
  const Eigen::Vector3d g_dist(c, s, 0.0);
  in.cov = F * in.cov * F.transpose() + yaw_var * g_yaw * g_yaw.transpose() +
           distance_var * g_dist * g_dist.transpose();
  in.d_scale = F * in.d_scale + distance * Eigen::Vector3d(c, s, 0.0);
  in.d_bias = F * in.d_bias;
  in.d_gyro_scale = F * in.d_gyro_scale;
  if (gyro) {
    in.d_gyro_scale += gyro_weight * dyaw * g_yaw;
    in.d_bias -= gyro_weight * dt * g_yaw;
  }
  in.x += distance * c;
  in.y += distance * s;
  in.yaw += dyaw;
  in.distance += std::abs(distance);
  in.wheel_travel += wheels;
  in.gyro_used = in.gyro_used && gyro;
}

void DeadReckoner::count_from(const hal::EncoderSample& s) {
  enc_t_ = s.t_ns;
  enc_left_ = s.left_ticks;
  enc_right_ = s.right_ticks;
  wheel_speed_ = 0.0;
  enc_yaw_rate_ = 0.0;
  last_motion_t_ = s.t_ns;
}

bool DeadReckoner::add_encoder(const hal::EncoderSample& s) {
  if (have_encoder_ && s.t_ns < enc_t_) {
    ++counters_.encoder_out_of_order;
    return false;
  }
  if (have_encoder_ && s.t_ns == enc_t_) {
    ++counters_.encoder_duplicate;
    return false;
  }
  const hal::WheelCalibration& w = calibration_.wheels;
  if (coasting()) {
    // After an outage: the takes covered it with the motion model up to seg_t_; the count
    // starts again here.
    ++counters_.encoder_outages;
    if (seg_t_ < s.t_ns) {
      coast(s.t_ns);
    }
    pending_distance_ = 0.0;
    pending_yaw_ = 0.0;
    pending_fused_correction_ = 0.0;
    count_from(s);
    ++counters_.encoder_accepted;
    return true;
  }
  if (!have_encoder_) {
    have_encoder_ = true;
    seg_t_ = s.t_ns;
    count_from(s);
    ++counters_.encoder_accepted;
    return true;
  }
  const double dt = seconds(s.t_ns - enc_t_);
  const std::int32_t dl_ticks = hal::tick_delta(s.left_ticks, enc_left_);
  const std::int32_t dr_ticks = hal::tick_delta(s.right_ticks, enc_right_);
  const double max_l = config_.max_wheel_speed_m_s * dt * w.ticks_per_meter_left + 2.0;
  const double max_r = config_.max_wheel_speed_m_s * dt * w.ticks_per_meter_right + 2.0;
  if (std::abs(static_cast<double>(dl_ticks)) > max_l ||
      std::abs(static_cast<double>(dr_ticks)) > max_r) {
    ++counters_.encoder_implausible;
    // Re-anchor: the interval's wheel motion is lost and the next interval is measured from
    // here. The segment given out so far stands (the gyro's heading goes on from its end); of
    // what a take extrapolated past the last sample, the part beyond this one stays pending.
    const double beyond =
        seg_t_ > s.t_ns ? seconds(seg_t_ - s.t_ns) / seconds(seg_t_ - enc_t_) : 0.0;
    pending_distance_ *= beyond;
    pending_yaw_ *= beyond;
    count_from(s);
    return false;
  }
  ++counters_.encoder_accepted;
  const double dl = static_cast<double>(dl_ticks) / w.ticks_per_meter_left;
  const double dr = static_cast<double>(dr_ticks) / w.ticks_per_meter_right;
  const double d = 0.5 * (dl + dr);
  const double dyaw_enc = (dr - dl) / w.wheel_base;
  if (std::abs(dl_ticks) > config_.standstill_max_ticks ||
      std::abs(dr_ticks) > config_.standstill_max_ticks) {
    last_motion_t_ = s.t_ns;
  }

  double th0 = 0.0;
  double th1 = 0.0;
  double live0 = 0.0;
  double live1 = 0.0;
  const bool gyro = gyro_angle(enc_t_, th0, live0) && gyro_angle(s.t_ns, th1, live1);
  double dyaw = gyro ? th1 - th0 : dyaw_enc;
  if (!gyro) {
    ++counters_.steps_without_gyro;
  }
  // With wheel_yaw fusion the interval's heading change is the fused one: the difference to the
  // gyro's goes into the segment below as well, with the fused variance and gyro weight.
  double fused_correction = 0.0;
  double fused_var = -1.0;
  double gyro_weight = 1.0;
  if (gyro && config_.wheel_yaw.enabled) {
    const double nd = calibration_.gyro.noise_density;
    const double q_left = 1.0 / w.ticks_per_meter_left;
    const double q_right = 1.0 / w.ticks_per_meter_right;
    const double k = w.distance_noise;
    WheelYawFusion::Reading r;
    r.gyro_yaw = dyaw;
    r.gyro_var = nd * nd * (live1 - live0);
    r.wheel_yaw = dyaw_enc;
    // Relative noise per wheel and the ticks' quantization (uniform, one tick wide).
    r.wheel_var = (k * k * (dl * dl + dr * dr) + (q_left * q_left + q_right * q_right) / 12.0) /
                  (w.wheel_base * w.wheel_base);
    r.distance = d;
    r.dt = live1 - live0;
    const WheelYawFusion::Fused f = wheel_yaw_.fuse(r);
    fused_correction = f.yaw - dyaw;
    fused_var = f.variance;
    gyro_weight = f.gyro_weight;
    dyaw = f.yaw;
  }
  const double mid = yaw_ + 0.5 * dyaw;
  x_ += d * std::cos(mid);
  y_ += d * std::sin(mid);
  yaw_ = wrap_angle(yaw_ + dyaw);

  if (seg_t_ >= s.t_ns) {
    // A take already extrapolated past this sample.
    pending_distance_ -= d;
    pending_yaw_ -= dyaw_enc;
    pending_fused_correction_ += fused_correction;
  } else {
    const double seg_d = d - pending_distance_;
    double seg_yaw = dyaw_enc - pending_yaw_;
    double yaw_var = config_.encoder_yaw_noise_rad_per_sqrt_m *
                     config_.encoder_yaw_noise_rad_per_sqrt_m * (std::abs(dl) + std::abs(dr));
    double ths = 0.0;
    double lives = 0.0;
    const bool seg_gyro = gyro && gyro_angle(seg_t_, ths, lives);
    double seg_dt = seconds(s.t_ns - seg_t_);
    double seg_weight = 1.0;
    if (seg_gyro) {
      seg_yaw = th1 - ths;
      const double nd = calibration_.gyro.noise_density;
      yaw_var = nd * nd * seg_dt;
      if (fused_var >= 0.0) {
        // A take inside the interval integrated its first part from the gyro alone.
        const double interval = live1 - live0;
        const double part = interval > 0.0 ? std::clamp((live1 - lives) / interval, 0.0, 1.0) : 1.0;
        seg_yaw += fused_correction + pending_fused_correction_;
        pending_fused_correction_ = 0.0;
        yaw_var = fused_var * part;
        seg_weight = gyro_weight;
      }
    }
    if (!seg_gyro && wheel_yaw_learnt()) {
      const WheelYawFusion::Fused f = wheel_yaw_.wheels_alone(seg_yaw, seg_d);
      seg_yaw = f.yaw;
      yaw_var += f.variance;
    }
    step(seg_d, seg_yaw, yaw_var, seg_dt, seg_gyro, std::abs(dl) + std::abs(dr), seg_weight);
    seg_t_ = s.t_ns;
    pending_distance_ = 0.0;
    pending_yaw_ = 0.0;
  }
  wheel_speed_ = d / dt;
  enc_yaw_rate_ = dyaw_enc / dt;
  enc_t_ = s.t_ns;
  enc_left_ = s.left_ticks;
  enc_right_ = s.right_ticks;
  return true;
}

OdometryIncrement DeadReckoner::take_increment(hal::TimeNs t_ns) {
  if (have_take_ && t_ns < last_take_t_) {
    ++counters_.increments_out_of_order;
    return OdometryIncrement{};
  }
  if (have_encoder_) {
    const auto reach = hal::from_seconds(config_.max_extrapolation_s);
    const hal::TimeNs target = std::clamp(t_ns, enc_t_ - reach, enc_t_ + reach);
    if (target != seg_t_ && !coasting()) {
      const double ahead = seconds(target - enc_t_);
      const double target_distance = wheel_speed_ * ahead;
      const double target_yaw = enc_yaw_rate_ * ahead;
      const double d = target_distance - pending_distance_;
      double dyaw = target_yaw - pending_yaw_;
      double yaw_var = config_.encoder_yaw_noise_rad_per_sqrt_m *
                       config_.encoder_yaw_noise_rad_per_sqrt_m * 2.0 * std::abs(d);
      double tha = 0.0;
      double thb = 0.0;
      double livea = 0.0;
      double liveb = 0.0;
      double dt = seconds(target - seg_t_);
      const bool gyro = gyro_angle(seg_t_, tha, livea) && gyro_angle(target, thb, liveb);
      if (gyro) {
        dyaw = thb - tha;
        const double nd = calibration_.gyro.noise_density;
        yaw_var = nd * nd * std::abs(dt);
      } else if (wheel_yaw_learnt()) {
        const WheelYawFusion::Fused f = wheel_yaw_.wheels_alone(dyaw, d);
        dyaw = f.yaw;
        yaw_var += f.variance;
      }
      step(d, dyaw, yaw_var, dt, gyro, 2.0 * std::abs(d), 1.0);
      pending_distance_ = target_distance;
      pending_yaw_ = target_yaw;
      seg_t_ = target;
    }
    // An outage when the gyro has gone on past the encoders (a frame stamped ahead of both is
    // extrapolation's, not the motion model's).
    const hal::TimeNs coast_to = std::min(t_ns, gyro_t_);
    if (have_gyro_ && coast_to > seg_t_ && coast_to > enc_t_ + reach) {
      coast(coast_to);
    }
  }
  const double dt_s = have_take_ ? seconds(t_ns - last_take_t_) : 0.0;
  OdometryIncrement out = camera_increment(inc_, dt_s);
  inc_ = Increment{};
  last_take_t_ = t_ns;
  have_take_ = true;
  return out;
}

OdometryIncrement DeadReckoner::camera_increment(const Increment& in, double dt_s) const {
  const double k = calibration_.wheels.distance_noise;
  const double bi = calibration_.gyro.bias_instability;
  const Eigen::Matrix3d planar = in.cov + k * k * in.d_scale * in.d_scale.transpose() +
                                 bi * bi * in.d_bias * in.d_bias.transpose() +
                                 config_.gyro_scale_error * config_.gyro_scale_error *
                                     in.d_gyro_scale * in.d_gyro_scale.transpose();
  // Body increment covariance over (dx, dy, dz, droll, dpitch, dyaw).
  Matrix6d Pb = Matrix6d::Zero();
  const int idx[3] = {0, 1, 5};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      Pb(idx[r], idx[c]) = planar(r, c);
    }
  }
  const double zn = config_.z_noise_m_per_sqrt_m;
  const double rp = config_.roll_pitch_noise_rad_per_sqrt_m;
  Pb(2, 2) = zn * zn * in.distance;
  Pb(3, 3) = rp * rp * in.distance;
  Pb(4, 4) = rp * rp * in.distance;

  Vector6d body;
  body << in.x, in.y, 0.0, 0.0, 0.0, in.yaw;
  Matrix6d J;
  const Vector6d u = camera_increment_from_body(body, R_body_c_, t_body_c_, &J);
  OdometryIncrement out;
  out.dx_c = u.head<3>();
  out.dpsi_c = u.tail<3>();
  const Matrix6d Q = J * Pb * J.transpose();
  out.Q = 0.5 * (Q + Q.transpose());
  out.distance_m = in.distance;
  out.dt_s = dt_s;
  out.gyro_used = in.gyro_used;
  return out;
}

}  // namespace cleanslam::slam_core
