#pragma once

#include "cleanslam/sim_hal/sim/scenario.hpp"

// What a camera does to the light after the lens has imaged it: vignetting, sensor noise and an
// auto-exposure loop that changes the gain in steps.
namespace cleanslam::sim_hal::sim {

// Relative illumination at pixel (x, y): (1 + a r^2)^-2 with r the distance from the principal
// point in focal lengths and a = camera.vignetting (a = 1: the cos^4 law of the pinhole).
[[nodiscard]] double vignetting_factor(const Scenario::Camera& camera, double x, double y);

// Standard deviation in gray levels of a pixel of mean `signal` (gray levels) at analog gain
// `gain`: read noise `read_sigma` and photon shot noise, variance `shot_gain` * signal, both
// at gain 1 and amplified with the gain (a dark scene brightened by the gain is noisier).
[[nodiscard]] double sensor_noise_sigma(double read_sigma, double shot_gain, double signal,
                                        double gain);

// Auto exposure: after each frame, moves the gain by whole steps of `step_ev` stops towards the
// gain that would have brought the frame's mean gray level to `target` (at most two steps a
// frame, gain within [1/16, 16]). The gain is always 2^(n * step_ev) for an integer n.
class AutoExposure {
 public:
  AutoExposure(double target, double step_ev) : target_(target), step_ev_(step_ev) {}
  [[nodiscard]] double gain() const;
  [[nodiscard]] int steps() const { return steps_; }
  void update(double mean_gray);

 private:
  double target_;
  double step_ev_;
  int steps_ = 0;
};

}  // namespace cleanslam::sim_hal::sim
