// DeadReckoner during an encoder outage: the distance from a motion model, the heading from the
// gyro (or a random walk when it is silent too).
#include <cmath>

#include "cleanslam/slam_core/dead_reckoner.hpp"

namespace cleanslam::slam_core {

bool DeadReckoner::coasting() const {
  return have_encoder_ && seg_t_ > enc_t_ + hal::from_seconds(config_.max_extrapolation_s);
}

void DeadReckoner::coast(hal::TimeNs t_ns) {
  const hal::TimeNs start = enc_t_ + hal::from_seconds(config_.max_extrapolation_s);
  const double tau = config_.outage_speed_time_constant_s;
  const double a = hal::to_seconds(seg_t_ - start);
  const double b = hal::to_seconds(t_ns - start);
  const double dt = b - a;
  // Mean distance: the integral of v0 exp(-t / tau) over [a, b].
  const double distance =
      tau > 0.0 ? wheel_speed_ * tau * (std::exp(-a / tau) - std::exp(-b / tau)) : 0.0;
  const double sv = config_.outage_speed_std_m_s;
  const double distance_var = 2.0 * sv * sv * tau * dt;
  double tha = 0.0;
  double thb = 0.0;
  double livea = 0.0;
  double liveb = 0.0;
  const bool gyro = gyro_angle(seg_t_, tha, livea) && gyro_angle(t_ns, thb, liveb);
  double dyaw = 0.0;
  double yaw_var = 0.0;
  if (gyro) {
    dyaw = thb - tha;
    const double nd = calibration_.gyro.noise_density;
    yaw_var = nd * nd * dt;
  } else {
    const double sr = config_.outage_yaw_rate_std_rad_s;
    yaw_var = sr * sr * tau * dt;
  }
  step(distance, dyaw, yaw_var, dt, gyro, 0.0, 1.0, 0.0, distance_var);
  seg_t_ = t_ns;
}

}  // namespace cleanslam::slam_core
