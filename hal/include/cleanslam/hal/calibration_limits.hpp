#pragma once

#include <sstream>
#include <string>

// The values of each calibration number that cleanslam accepts. The dataset's sensors.yaml and the
// firmware configuration's `calibration` section are both checked against these, so that a
// recording and a robot refuse the same nonsense (a negative noise, a lever arm of 1e7 m).
namespace cleanslam::hal::calibration_limits {

struct Limit {
  double lo;
  double hi;
  bool lo_open;  // lo itself is outside
  [[nodiscard]] constexpr bool contains(double v) const {
    return (lo_open ? v > lo : v >= lo) && v <= hi;
  }
};

// "v is out of range (lo, hi]", as the firmware configuration words it for every key.
inline std::string out_of_range(double v, Limit limit) {
  std::ostringstream s;
  s << v << " is out of range " << (limit.lo_open ? "(" : "[") << limit.lo << ", " << limit.hi
    << "]";
  return s.str();
}

inline constexpr Limit kFocalPx{0.0, 1e5, true};
inline constexpr Limit kPrincipalPointPx{-1e4, 1e4, false};
inline constexpr Limit kDistortion{-100.0, 100.0, false};  // each of k1 k2 p1 p2
inline constexpr Limit kPixelNoisePx{0.0, 100.0, true};
inline constexpr Limit kTimeOffsetS{-1.0, 1.0, false};
// A camera time offset beyond this is accepted with a warning: more than a frame period at 2 Hz.
inline constexpr double kPlausibleTimeOffsetS = 0.5;
inline std::string implausible_time_offset(double v) {
  std::ostringstream s;
  s << v << " s is more than " << kPlausibleTimeOffsetS
    << " s: frames are matched to the odometry that far away (is it in seconds?)";
  return s.str();
}
inline constexpr Limit kTicksPerMeter{0.0, 1e7, true};
inline constexpr Limit kWheelBaseM{0.0, 10.0, true};
inline constexpr Limit kFraction{0.0, 1.0, false};  // distance_noise and both scale_error
inline constexpr Limit kNoiseDensity{0.0, 1.0, true};
inline constexpr Limit kGyroBias{0.0, 1.0, false};  // bias_instability and bias_walk

}  // namespace cleanslam::hal::calibration_limits
