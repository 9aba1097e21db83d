#include "cleanslam/sim_hal/sim/camera_effects.hpp"

#include <algorithm>
#include <cmath>

namespace cleanslam::sim_hal::sim {

double vignetting_factor(const Scenario::Camera& c, double x, double y) {
  const double nx = (x - c.cx) / c.fx, ny = (y - c.cy) / c.fy;
  const double q = 1.0 + c.vignetting * (nx * nx + ny * ny);
  return 1.0 / (q * q);
}

double sensor_noise_sigma(double read_sigma, double shot_gain, double signal, double gain) {
  const double read = read_sigma * gain;
  return std::sqrt(read * read + shot_gain * gain * std::max(0.0, signal));
}

double AutoExposure::gain() const {
  return std::exp2(static_cast<double>(steps_) * step_ev_);
}

void AutoExposure::update(double mean_gray) {
  const double error_ev = std::log2(target_ / std::max(mean_gray, 1.0));
  const long step = std::clamp(std::lround(error_ev / step_ev_), -2L, 2L);
  const int limit = static_cast<int>(std::floor(4.0 / step_ev_));
  steps_ = std::clamp(steps_ + static_cast<int>(step), -limit, limit);
}

}  // namespace cleanslam::sim_hal::sim
