#include "cleanslam/calibrate/allan_deviation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include "cleanslam/calibrate/sample_files.hpp"
#include "cleanslam/calibrate/text.hpp"

namespace cleanslam::calibrate {
namespace {

// The overlapping Allan variance at cluster size m from the integrated angle theta.
double allan_variance(const std::vector<double>& theta, std::size_t m, double dt) {
  const std::size_t n = theta.size() - 1;  // rate samples
  double sum = 0.0;
  for (std::size_t k = 0; k + 2 * m <= n; ++k) {
    const double d = theta[k + 2 * m] - 2.0 * theta[k + m] + theta[k];
    sum += d * d;
  }
  const double tau = static_cast<double>(m) * dt;
  return sum / (2.0 * tau * tau * static_cast<double>(n - 2 * m + 1));
}

// The angle integrated from the rates: theta[k] after k samples.
std::vector<double> integrated_angles(const std::vector<double>& rates, double dt) {
  std::vector<double> theta(rates.size() + 1, 0.0);
  for (std::size_t k = 0; k < rates.size(); ++k) {
    theta[k + 1] = theta[k] + rates[k] * dt;
  }
  return theta;
}

}  // namespace

std::vector<AllanPoint> allan_deviation(const std::vector<double>& rates, double dt,
                                        int per_decade) {
  const std::vector<double> theta = integrated_angles(rates, dt);
  std::vector<AllanPoint> out;
  const std::size_t max_m = rates.size() / 9;
  std::size_t last = 0;
  for (int i = 0;; ++i) {
    const auto m = static_cast<std::size_t>(std::llround(std::pow(10.0, double(i) / per_decade)));
    if (m > max_m) {
      break;
    }
    if (m == last) {
      continue;
    }
    last = m;
    out.push_back({static_cast<double>(m) * dt, std::sqrt(allan_variance(theta, m, dt))});
  }
  return out;
}

readers::Result<GyroNoise> gyro_noise(const readers::Dataset& d, const GyroNoiseOptions& o) {
  using GyroResult = readers::Result<GyroNoise>;
  const std::string gyro_file = samples_file(d, Samples::kGyro);
  const auto& g = d.gyro;
  if (g.size() < 3) {
    return GyroResult::failure(gyro_file + ": fewer than three samples");
  }
  for (std::size_t k = 1; k < d.encoders.size(); ++k) {
    const auto& a = d.encoders[k - 1];
    const auto& b = d.encoders[k];
    if (a.left_ticks != b.left_ticks || a.right_ticks != b.right_ticks) {
      return GyroResult::failure(
          samples_file(d, Samples::kEncoders) + ": " + sample_place(d, Samples::kEncoders, k) +
          ": the wheels move (t_ns " + std::to_string(b.t_ns) +
          "); the gyro's noise needs a recording of the robot standing still");
    }
  }
  GyroNoise out;
  out.samples = static_cast<int>(g.size());
  out.duration_s = 1e-9 * static_cast<double>(g.back().t_ns - g.front().t_ns);
  if (out.duration_s < o.min_duration_s) {
    return GyroResult::failure(gyro_file + ": the standstill lasts " + fixed(out.duration_s, 1) +
                               " s; the Allan deviation at tau = 1 s needs at least " +
                               fixed(o.min_duration_s, 0) +
                               " s (--min-duration) to be known within about 7 %: record longer");
  }
  std::vector<hal::TimeNs> gaps;
  for (std::size_t k = 1; k < g.size(); ++k) {
    gaps.push_back(g[k].t_ns - g[k - 1].t_ns);
  }
  std::vector<hal::TimeNs> sorted = gaps;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double dt = 1e-9 * static_cast<double>(sorted[sorted.size() / 2]);
  out.rate_hz = 1.0 / dt;
  for (std::size_t k = 0; k < gaps.size(); ++k) {
    if (1e-9 * static_cast<double>(gaps[k]) > o.max_gap_factor * dt) {
      return GyroResult::failure(gyro_file + ": line " + std::to_string(k + 3) + ": a gap of " +
                                 fixed(1e-9 * static_cast<double>(gaps[k]), 3) + " s after t_ns " +
                                 std::to_string(g[k].t_ns) + " (the period is " + fixed(dt, 4) +
                                 " s): the Allan deviation needs evenly spaced samples");
    }
  }
  std::vector<double> rates;
  rates.reserve(g.size());
  double sum = 0.0;
  for (const hal::GyroSample& s : g) {
    rates.push_back(s.wz_rad_s);
    sum += s.wz_rad_s;
  }
  out.bias_rad_s = sum / static_cast<double>(g.size());
  out.curve = allan_deviation(rates, dt);
  // At tau = 1 s exactly (one cluster of round(1 / dt) samples).
  {
    const std::vector<double> theta = integrated_angles(rates, dt);
    const auto m = static_cast<std::size_t>(std::max(1L, std::lround(1.0 / dt)));
    const double tau = static_cast<double>(m) * dt;
    out.noise_density = std::sqrt(allan_variance(theta, m, dt) * tau);
  }
  double log_sum = 0.0;
  int fitted = 0;
  for (const AllanPoint& p : out.curve) {
    if (p.tau_s >= 10.0 * dt - 1e-12 && p.tau_s <= 1.0 + 1e-12) {
      log_sum += std::log(p.deviation_rad_s * std::sqrt(p.tau_s));
      ++fitted;
    }
  }
  out.slope_fit_density = fitted > 0 ? std::exp(log_sum / fitted) : out.noise_density;
  const auto lowest = std::min_element(
      out.curve.begin(), out.curve.end(),
      [](const auto& a, const auto& b) { return a.deviation_rad_s < b.deviation_rad_s; });
  out.bias_instability = lowest->deviation_rad_s / 0.664;
  out.bias_instability_tau_s = lowest->tau_s;
  return out;
}

}  // namespace cleanslam::calibrate
