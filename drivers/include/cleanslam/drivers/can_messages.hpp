#pragma once

#include <array>
#include <cstdint>

#include "cleanslam/hal/pose.hpp"

// The base board's CAN message map (docs/can.md, docs/cleanslam.dbc). Standard 11-bit ids,
// 8 data bytes, little-endian (Intel) signals.
namespace cleanslam::drivers::can_map {

inline constexpr std::uint32_t kEncoderId = 0x101;       // base board -> us, 20 Hz
inline constexpr std::uint32_t kGyroId = 0x102;          // base board -> us, 100 Hz
inline constexpr std::uint32_t kPosePositionId = 0x201;  // us -> bus, each estimate
inline constexpr std::uint32_t kPoseYawId = 0x202;       // us -> bus, each estimate
inline constexpr std::uint8_t kFrameLength = 8;

inline constexpr double kGyroRateScale = 1e-6;       // rad/s per LSB, int32
inline constexpr double kTemperatureScale = 0.01;    // degC per LSB, int16
inline constexpr double kPositionScale = 1e-4;       // m per LSB, int24
inline constexpr double kAngleScale = 1e-4;          // rad per LSB, yaw int16, sigma uint16
inline constexpr double kSigmaPositionScale = 1e-4;  // m per LSB, uint16

struct Frame {
  std::uint32_t id = 0;
  std::uint8_t length = 0;
  std::array<std::uint8_t, 8> data{};
};

// Encoder frame: cumulative ticks as signed 24-bit counters that wrap.
struct EncoderMessage {
  std::int32_t left_ticks24 = 0;   // sign-extended
  std::int32_t right_ticks24 = 0;  // sign-extended
  std::uint8_t seq = 0;
  std::uint8_t status = 0;
};

struct GyroMessage {
  std::int32_t rate_raw = 0;  // kGyroRateScale rad/s per LSB, counter-clockwise positive
  std::int16_t temperature_raw = 0;
  std::uint8_t seq = 0;
  std::uint8_t status = 0;  // bit 0: rate saturated

  [[nodiscard]] double rate_rad_s() const { return rate_raw * kGyroRateScale; }
  [[nodiscard]] double temperature_c() const { return temperature_raw * kTemperatureScale; }
};
inline constexpr std::uint8_t kGyroSaturated = 1U << 0;

struct PoseMessages {
  Frame position;
  Frame yaw_quality;
};

[[nodiscard]] bool decode(const Frame& frame, EncoderMessage& out);
[[nodiscard]] bool decode(const Frame& frame, GyroMessage& out);
[[nodiscard]] Frame encode(const EncoderMessage& message);
[[nodiscard]] Frame encode(const GyroMessage& message);

// The two pose frames of one estimate; values beyond a signal's range saturate.
[[nodiscard]] PoseMessages encode_pose(const hal::PoseEstimate& pose, std::uint8_t seq);

// Yaw (rad) of a quaternion w, x, y, z under C_wc = Rz(yaw) Ry(pitch) Rx(roll).
[[nodiscard]] double yaw_of(const std::array<double, 4>& q_wxyz);

// Extends a wrapping 24-bit counter to the 32-bit wrapping counter of hal::EncoderSample.
class TickExtender {
 public:
  std::int32_t extend(std::int32_t ticks24);
  void reset() { started_ = false; }

 private:
  bool started_ = false;
  std::uint32_t last24_ = 0;
  std::uint32_t total_ = 0;
};

// Dropped frames from an 8-bit sequence counter.
class SequenceTracker {
 public:
  enum class Result : std::uint8_t { kFirst, kInOrder, kGap, kDuplicate, kOutOfOrder };
  Result observe(std::uint8_t seq);
  // Frames missing before the last observed one (for kGap).
  [[nodiscard]] unsigned last_gap() const { return last_gap_; }
  // Running 32-bit sequence number counting missing frames too; never decreases.
  [[nodiscard]] std::uint32_t extended() const { return extended_; }
  void reset() { started_ = false; }

 private:
  bool started_ = false;
  bool ever_started_ = false;
  std::uint8_t last_ = 0;
  unsigned last_gap_ = 0;
  std::uint32_t extended_ = 0;
};

}  // namespace cleanslam::drivers::can_map
