#pragma once

#include <cstdint>

namespace cleanslam::hal {

// Nanoseconds of one monotonic clock shared by every sample of a run.
using TimeNs = std::int64_t;

inline constexpr TimeNs kNsPerSecond = 1'000'000'000;
inline constexpr TimeNs kNsPerMillisecond = 1'000'000;

constexpr double to_seconds(TimeNs t) {
  return static_cast<double>(t) * 1e-9;
}
constexpr TimeNs from_seconds(double s) {
  return static_cast<TimeNs>(s * 1e9);
}

}  // namespace cleanslam::hal
