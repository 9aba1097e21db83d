#pragma once

#include <vector>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/result.hpp"

// The gyro's noise from a standstill by the Allan deviation (IEEE Std 952-1997, Annex C): white
// rate noise (angle random walk N) falls as N / sqrt(tau), so the noise density is the deviation
// read at tau = 1 s; the flat bottom of the curve is the bias instability (its minimum / 0.664).
namespace cleanslam::calibrate {

struct AllanPoint {
  double tau_s = 0.0;
  double deviation_rad_s = 0.0;
};

// Overlapping Allan deviation of evenly sampled rates (spacing dt_s) at cluster times of about
// `per_decade` logarithmic steps, up to a ninth of the record.
std::vector<AllanPoint> allan_deviation(const std::vector<double>& rates, double dt_s,
                                        int per_decade = 10);

struct GyroNoiseOptions {
  double min_duration_s = 100.0;  // the deviation at 1 s is then known to about 7 %
  double max_gap_factor = 5.0;    // a sample gap longer than this many periods is refused
};

struct GyroNoise {
  double bias_rad_s = 0.0;
  double noise_density = 0.0;      // rad/s/sqrt(Hz): the deviation at tau = 1 s
  double slope_fit_density = 0.0;  // N fitted to the -1/2 slope for tau in [10 dt, 1 s]
  double bias_instability = 0.0;   // rad/s: the curve's minimum / 0.664
  double bias_instability_tau_s = 0.0;
  double duration_s = 0.0;
  double rate_hz = 0.0;
  int samples = 0;
  std::vector<AllanPoint> curve;
};

// Refused, naming the file (samples_file), when the recording is shorter than the minimum, the
// wheels moved (its encoder samples) or the gyro has a gap.
readers::Result<GyroNoise> gyro_noise(const readers::Dataset& dataset,
                                      const GyroNoiseOptions& options);

}  // namespace cleanslam::calibrate
