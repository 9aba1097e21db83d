#pragma once

#include <cstdint>
#include <limits>

namespace cleanslam::hal {

// Nanoseconds of one monotonic clock shared by every sample of a run.
using TimeNs = std::int64_t;

inline constexpr TimeNs kNsPerSecond = 1'000'000'000;
inline constexpr TimeNs kNsPerMillisecond = 1'000'000;
// Events stamped later than this after a run's first are refused as corrupt (loop.max_span_s).
inline constexpr TimeNs kDefaultMaxSpanNs = 86'400 * kNsPerSecond;

constexpr double to_seconds(TimeNs t) {
  return static_cast<double>(t) * 1e-9;
}
constexpr TimeNs from_seconds(double s) {
  return static_cast<TimeNs>(s * 1e9);
}

inline constexpr TimeNs kTimeMax = std::numeric_limits<TimeNs>::max();
inline constexpr TimeNs kTimeMin = std::numeric_limits<TimeNs>::min();

// a + b and a - b clamped to the range of TimeNs: a corrupt stamp near either end cannot overflow.
constexpr TimeNs add_saturated(TimeNs a, TimeNs b) {
  TimeNs r = 0;
  if (__builtin_add_overflow(a, b, &r)) {
    return b > 0 ? kTimeMax : kTimeMin;
  }
  return r;
}
constexpr TimeNs sub_saturated(TimeNs a, TimeNs b) {
  TimeNs r = 0;
  if (__builtin_sub_overflow(a, b, &r)) {
    return b < 0 ? kTimeMax : kTimeMin;
  }
  return r;
}

}  // namespace cleanslam::hal
