// DeadReckoner during an encoder outage: the distance from a motion model (the robot keeps its
// last wheel speed), the heading from the gyro (or a random walk when it is silent too).
#include <algorithm>
#include <cmath>

#include "cleanslam/slam_core/dead_reckoner.hpp"

namespace cleanslam::slam_core {

namespace {
// Variance of the distance travelled over t by a speed error that follows a stationary
// Ornstein-Uhlenbeck process with time constant tau and std. dev. sv: (sv t)^2 while t << tau
// (the error persists), 2 sv^2 tau t in the long run.
double ou_distance_variance(double t, double tau, double sv) {
  if (!(tau > 0.0)) {
    return 0.0;
  }
  const double x = t / tau;
  if (x < 1e-3) {
    return sv * sv * t * t * (1.0 - x / 3.0);
  }
  return 2.0 * sv * sv * tau * tau * (x - 1.0 + std::exp(-x));
}
}  // namespace

bool DeadReckoner::coasting() const {
  return have_encoder_ && seg_t_ > enc_t_ + hal::from_seconds(config_.max_extrapolation_s);
}

void DeadReckoner::coast(hal::TimeNs t_ns) {
  const hal::TimeNs start = enc_t_ + hal::from_seconds(config_.max_extrapolation_s);
  const double tau = config_.outage_speed_time_constant_s;
  const double a = hal::to_seconds(seg_t_ - start);
  const double b = hal::to_seconds(t_ns - start);
  const double dt = b - a;
  // The drive holds its speed whether or not the encoders report it: the mean is the last one's.
  const double distance = wheel_speed_ * dt;
  const double sv = config_.outage_speed_std_m_s;
  // The EKF takes increments as independent: each gets the growth of the whole outage's variance
  // (more than the increment's own share of a persistent error, never less).
  const double distance_var =
      std::max(0.0, ou_distance_variance(b, tau, sv) - ou_distance_variance(a, tau, sv));
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
  step(distance, dyaw, yaw_var, dt, gyro, 0.0, 1.0, distance_var);
  seg_t_ = t_ns;
}

}  // namespace cleanslam::slam_core
