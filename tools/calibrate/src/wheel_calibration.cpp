#include "cleanslam/calibrate/wheel_calibration.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include "cleanslam/calibrate/sample_files.hpp"
#include "cleanslam/calibrate/text.hpp"

namespace cleanslam::calibrate {
namespace {

using WheelResult = readers::Result<WheelCalibration>;

enum class Motion { kStill, kStraight, kTurn, kMixed };

// Tick increments of one encoder interval (the counters are 32-bit and wrap).
struct Interval {
  hal::TimeNs t0 = 0;
  hal::TimeNs t1 = 0;
  double left = 0.0;
  double right = 0.0;
  Motion motion = Motion::kStill;
};

std::int32_t tick_delta(std::int32_t a, std::int32_t b) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(b) - static_cast<std::uint32_t>(a));
}

std::vector<Interval> intervals_of(const std::vector<hal::EncoderSample>& e) {
  std::vector<Interval> out;
  for (std::size_t k = 1; k < e.size(); ++k) {
    Interval iv{e[k - 1].t_ns, e[k].t_ns,
                static_cast<double>(tick_delta(e[k - 1].left_ticks, e[k].left_ticks)),
                static_cast<double>(tick_delta(e[k - 1].right_ticks, e[k].right_ticks))};
    if (iv.left == 0.0 && iv.right == 0.0) {
      iv.motion = Motion::kStill;
    } else if (iv.left * iv.right > 0.0) {
      iv.motion = Motion::kStraight;
    } else if (iv.left * iv.right < 0.0) {
      iv.motion = Motion::kTurn;
    } else {
      iv.motion = Motion::kMixed;
    }
    out.push_back(iv);
  }
  return out;
}

// The gyro's angle over (t0, t1], less the bias: each sample is the mean rate since the one before.
double gyro_angle(const std::vector<hal::GyroSample>& g, hal::TimeNs t0, hal::TimeNs t1,
                  double bias) {
  double angle = 0.0;
  for (std::size_t k = 1; k < g.size(); ++k) {
    if (g[k].t_ns <= t0) {
      continue;
    }
    if (g[k].t_ns > t1) {
      break;
    }
    angle += (g[k].wz_rad_s - bias) * 1e-9 * static_cast<double>(g[k].t_ns - g[k - 1].t_ns);
  }
  return angle;
}

}  // namespace

WheelResult calibrate_wheels(const readers::Dataset& d, const WheelCalibrationOptions& o) {
  const std::string enc_file = samples_file(d, Samples::kEncoders);
  const std::string gyro_file = samples_file(d, Samples::kGyro);
  if (!(o.straight_length_m > 0.0)) {
    return WheelResult::failure("--straight: the straight drive's length must be positive, got " +
                                fixed(o.straight_length_m, 3) + " m");
  }
  if (d.encoders.size() < 2) {
    return WheelResult::failure(enc_file + ": fewer than two samples");
  }
  if (d.gyro.size() < 2) {
    return WheelResult::failure(gyro_file + ": fewer than two samples");
  }
  const std::vector<Interval> iv = intervals_of(d.encoders);
  WheelCalibration c;

  // The standstill before the first motion gives the gyro's bias.
  std::size_t first_motion = 0;
  while (first_motion < iv.size() && iv[first_motion].motion == Motion::kStill) {
    ++first_motion;
  }
  if (first_motion == iv.size()) {
    return WheelResult::failure(enc_file +
                                ": the wheels never move: no calibration drive in this recording");
  }
  const hal::TimeNs still_end = iv[first_motion].t0;
  const hal::TimeNs still_begin = std::max(d.encoders.front().t_ns, d.gyro.front().t_ns);
  c.standstill_s = 1e-9 * static_cast<double>(still_end - still_begin);
  if (c.standstill_s < o.min_standstill_s) {
    return WheelResult::failure(
        enc_file + ": the wheels move " + fixed(c.standstill_s, 1) +
        " s after the recording starts; the gyro's bias needs a standstill of at "
        "least " +
        fixed(o.min_standstill_s, 1) + " s first (record it standing still longer)");
  }
  double sum = 0.0;
  int n = 0;
  for (const hal::GyroSample& s : d.gyro) {
    if (s.t_ns > still_begin && s.t_ns <= still_end) {
      sum += s.wz_rad_s;
      ++n;
    }
  }
  if (n == 0) {
    return WheelResult::failure(gyro_file + ": no sample during the standstill at the start");
  }
  c.gyro_bias_rad_s = sum / n;

  // The straight drive's ticks and the gyro's heading change over it; each turn in place as its
  // own run of intervals.
  struct Turn {
    double left = 0.0, right = 0.0, angle = 0.0;
  };
  std::vector<Turn> turns;
  for (std::size_t k = 0; k < iv.size(); ++k) {
    if (iv[k].motion == Motion::kMixed) {
      ++c.mixed_intervals;
    }
    if (iv[k].motion == Motion::kStraight) {
      c.straight_ticks_left += iv[k].left;
      c.straight_ticks_right += iv[k].right;
      c.straight_yaw_rad += gyro_angle(d.gyro, iv[k].t0, iv[k].t1, c.gyro_bias_rad_s);
    }
    if (iv[k].motion != Motion::kTurn) {
      continue;
    }
    Turn t;
    const hal::TimeNs t0 = iv[k].t0;
    for (; k < iv.size() && iv[k].motion == Motion::kTurn; ++k) {
      t.left += iv[k].left;
      t.right += iv[k].right;
    }
    --k;
    t.angle = gyro_angle(d.gyro, t0, iv[k].t1, c.gyro_bias_rad_s);
    turns.push_back(t);
  }
  if (c.straight_ticks_left <= 0.0 || c.straight_ticks_right <= 0.0) {
    return WheelResult::failure(
        enc_file + ": no straight forward drive (both wheels turning forward) in the recording");
  }
  for (const Turn& t : turns) {
    c.turn_angle_rad += std::abs(t.angle);
  }
  c.turns = static_cast<int>(turns.size());
  if (c.turn_angle_rad < o.min_turn_rad) {
    return WheelResult::failure(
        gyro_file + ": the turns in place (the wheels turning opposite ways in " + enc_file +
        ") add up to " + fixed(c.turn_angle_rad * 180.0 / std::numbers::pi, 0) +
        " degrees; the wheel base needs at least " +
        fixed(o.min_turn_rad * 180.0 / std::numbers::pi, 0) + " degrees of turning in place");
  }

  // Each wheel rolls L -+ b/2 * dyaw on the straight drive; in a turn in place the wheels'
  // distances differ by b * dyaw. b and the ticks per metre depend on each other through the
  // straight drive's small heading change: a few rounds settle them.
  double b = d.calibration.wheels.wheel_base > 0.0 ? d.calibration.wheels.wheel_base : 0.25;
  const double length = o.straight_length_m;
  for (int round = 0; round < 8; ++round) {
    c.ticks_per_meter_left = c.straight_ticks_left / (length - 0.5 * b * c.straight_yaw_rad);
    c.ticks_per_meter_right = c.straight_ticks_right / (length + 0.5 * b * c.straight_yaw_rad);
    double num = 0.0, den = 0.0;
    for (const Turn& t : turns) {
      const double diff = t.right / c.ticks_per_meter_right - t.left / c.ticks_per_meter_left;
      num += diff * t.angle;
      den += t.angle * t.angle;
    }
    b = num / den;
  }
  c.wheel_base_m = b;
  if (turns.size() > 1) {
    double ss = 0.0;
    for (const Turn& t : turns) {
      const double bt =
          (t.right / c.ticks_per_meter_right - t.left / c.ticks_per_meter_left) / t.angle;
      ss += (bt - b) * (bt - b);
    }
    c.wheel_base_spread_m = std::sqrt(ss / static_cast<double>(turns.size() - 1));
  }
  if (!(b > 0.0) || b > 10.0) {
    return WheelResult::failure(
        enc_file + ": the turns give a wheel base of " + fixed(b, 4) +
        " m, outside (0, 10]: do the wheels' signs and the gyro's (counter-clockwise "
        "positive) agree?");
  }
  for (const double tpm : {c.ticks_per_meter_left, c.ticks_per_meter_right}) {
    if (tpm < 100.0 || tpm > 1e7) {
      return WheelResult::failure(enc_file + ": the straight drive gives " + fixed(tpm, 1) +
                                  " ticks per metre, outside [100, 1e7]: is --straight " +
                                  fixed(length, 3) + " m the length driven?");
    }
  }
  return c;
}

}  // namespace cleanslam::calibrate
