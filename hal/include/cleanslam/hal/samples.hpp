#pragma once

#include <cstdint>

#include "cleanslam/hal/time.hpp"

namespace cleanslam::hal {

// Yaw-rate gyro sample (100 Hz). Body frame: x forward, y left, z up; counter-clockwise positive.
struct GyroSample {
  TimeNs t_ns = 0;
  double wz_rad_s = 0.0;
  double wx_rad_s = 0.0;
  double wy_rad_s = 0.0;
  bool has_xy = false;
  std::uint32_t seq = 0;
};

// Wheel encoders (20 Hz): cumulative signed counts since an arbitrary start, wrapping at 32 bits.
struct EncoderSample {
  TimeNs t_ns = 0;
  std::int32_t left_ticks = 0;
  std::int32_t right_ticks = 0;
  std::uint32_t seq = 0;
};

// Signed difference of two wrapping 32-bit tick counters (a - b), correct across wrap-around.
constexpr std::int32_t tick_delta(std::int32_t a, std::int32_t b) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) - static_cast<std::uint32_t>(b));
}

}  // namespace cleanslam::hal
