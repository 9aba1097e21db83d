#pragma once

#include <array>
#include <cstdint>

#include "cleanslam/hal/time.hpp"

namespace cleanslam::hal {

// Health flags of the estimate, one bit per condition; zero means all is well.
enum HealthFlag : std::uint32_t {
  kHealthOk = 0,
  kGyroSilent = 1U << 0,      // heading from encoders alone, inflated noise
  kEncodersSilent = 1U << 1,  // distance from a motion model, heading from the gyro
  kCameraSilent = 1U << 2,    // dead reckoning only
  kStandingStill = 1U << 3,   // no visual update (Section 2.4)
  kLifted = 1U << 4,          // wheel-drop switch: pose lost
  kPoseLost = 1U << 5,        // relocalizing, or the position std. dev. beyond its threshold
  kFewLandmarks = 1U << 6,
  kInputRejected = 1U << 7,  // some input was rejected since the last estimate
};

// Pose of the body frame in the world frame (z up), quaternion w, x, y, z, with its 6x6
// covariance over (x, y, z, roll, pitch, yaw), row-major.
struct PoseEstimate {
  TimeNs t_ns = 0;
  std::array<double, 3> position_m{};
  std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};
  std::array<double, 36> covariance{};
  std::uint32_t health = kHealthOk;
  std::uint16_t landmarks_in_map = 0;
  std::uint16_t landmarks_in_view = 0;
};

}  // namespace cleanslam::hal
