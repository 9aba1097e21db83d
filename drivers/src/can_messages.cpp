#include "cleanslam/drivers/can_messages.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cleanslam::drivers::can_map {
namespace {

std::uint32_t get_u(const Frame& f, int offset, int bytes) {
  std::uint32_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) {
    v = (v << 8) | f.data[static_cast<std::size_t>(offset + i)];
  }
  return v;
}

std::int32_t sign_extend(std::uint32_t v, int bits) {
  const std::uint32_t sign = 1U << (bits - 1);
  const std::uint32_t mask = bits == 32 ? 0xFFFFFFFFU : (1U << bits) - 1U;
  v &= mask;
  return static_cast<std::int32_t>((v ^ sign) - sign);
}

void put_u(Frame& f, int offset, int bytes, std::uint32_t v) {
  for (int i = 0; i < bytes; ++i) {
    f.data[static_cast<std::size_t>(offset + i)] = static_cast<std::uint8_t>(v >> (8 * i));
  }
}

// Rounds value/scale to the nearest integer in [lo, hi].
std::int64_t quantize(double value, double scale, std::int64_t lo, std::int64_t hi) {
  if (!std::isfinite(value)) {
    return value > 0 ? hi : (value < 0 ? lo : hi);
  }
  const double q = std::round(value / scale);
  if (q <= static_cast<double>(lo)) {
    return lo;
  }
  if (q >= static_cast<double>(hi)) {
    return hi;
  }
  return static_cast<std::int64_t>(q);
}

Frame empty_frame(std::uint32_t id) {
  Frame f;
  f.id = id;
  f.length = kFrameLength;
  return f;
}

}  // namespace

bool decode(const Frame& frame, EncoderMessage& out) {
  if (frame.id != kEncoderId || frame.length != kFrameLength) {
    return false;
  }
  out.left_ticks24 = sign_extend(get_u(frame, 0, 3), 24);
  out.right_ticks24 = sign_extend(get_u(frame, 3, 3), 24);
  out.seq = frame.data[6];
  out.status = frame.data[7];
  return true;
}

bool decode(const Frame& frame, GyroMessage& out) {
  if (frame.id != kGyroId || frame.length != kFrameLength) {
    return false;
  }
  out.rate_raw = sign_extend(get_u(frame, 0, 4), 32);
  out.temperature_raw = static_cast<std::int16_t>(sign_extend(get_u(frame, 4, 2), 16));
  out.seq = frame.data[6];
  out.status = frame.data[7];
  return true;
}

Frame encode(const EncoderMessage& message) {
  Frame f = empty_frame(kEncoderId);
  put_u(f, 0, 3, static_cast<std::uint32_t>(message.left_ticks24));
  put_u(f, 3, 3, static_cast<std::uint32_t>(message.right_ticks24));
  f.data[6] = message.seq;
  f.data[7] = message.status;
  return f;
}

Frame encode(const GyroMessage& message) {
  Frame f = empty_frame(kGyroId);
  put_u(f, 0, 4, static_cast<std::uint32_t>(message.rate_raw));
  put_u(f, 4, 2, static_cast<std::uint32_t>(static_cast<std::uint16_t>(message.temperature_raw)));
  f.data[6] = message.seq;
  f.data[7] = message.status;
  return f;
}

double yaw_of(const std::array<double, 4>& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

PoseMessages encode_pose(const hal::PoseEstimate& pose, std::uint8_t seq) {
  constexpr std::int64_t kInt24Max = (1 << 23) - 1;
  PoseMessages m{empty_frame(kPosePositionId), empty_frame(kPoseYawId)};
  put_u(m.position, 0, 3,
        static_cast<std::uint32_t>(
            quantize(pose.position_m[0], kPositionScale, -kInt24Max, kInt24Max)));
  put_u(m.position, 3, 3,
        static_cast<std::uint32_t>(
            quantize(pose.position_m[1], kPositionScale, -kInt24Max, kInt24Max)));
  m.position.data[6] = seq;
  m.position.data[7] = 0;

  const double var_xy = std::max(pose.covariance[0], pose.covariance[7]);
  const double var_yaw = pose.covariance[35];
  constexpr std::int64_t kU16Max = std::numeric_limits<std::uint16_t>::max();
  put_u(m.yaw_quality, 0, 2,
        static_cast<std::uint32_t>(quantize(yaw_of(pose.orientation_wxyz), kAngleScale,
                                            std::numeric_limits<std::int16_t>::min(),
                                            std::numeric_limits<std::int16_t>::max())));
  put_u(m.yaw_quality, 2, 2,
        static_cast<std::uint32_t>(
            quantize(var_xy >= 0.0 ? std::sqrt(var_xy) : std::numeric_limits<double>::infinity(),
                     kSigmaPositionScale, 0, kU16Max)));
  put_u(m.yaw_quality, 4, 2,
        static_cast<std::uint32_t>(
            quantize(var_yaw >= 0.0 ? std::sqrt(var_yaw) : std::numeric_limits<double>::infinity(),
                     kAngleScale, 0, kU16Max)));
  m.yaw_quality.data[6] = seq;
  m.yaw_quality.data[7] = static_cast<std::uint8_t>(pose.health & 0xFFU);
  return m;
}

std::int32_t TickExtender::extend(std::int32_t ticks24) {
  const std::uint32_t raw = static_cast<std::uint32_t>(ticks24) & 0xFFFFFFU;
  if (!started_) {
    started_ = true;
    total_ = static_cast<std::uint32_t>(sign_extend(raw, 24));
  } else {
    total_ += static_cast<std::uint32_t>(sign_extend(raw - last24_, 24));
  }
  last24_ = raw;
  return static_cast<std::int32_t>(total_);
}

SequenceTracker::Result SequenceTracker::observe(std::uint8_t seq) {
  last_gap_ = 0;
  if (!started_) {
    // After a resynchronization the running number goes on, so it never runs backwards.
    extended_ = ever_started_ ? extended_ + 1U : seq;
    started_ = true;
    ever_started_ = true;
    last_ = seq;
    return Result::kFirst;
  }
  const auto diff = static_cast<std::uint8_t>(seq - last_);
  if (diff == 0) {
    return Result::kDuplicate;
  }
  if (diff >= 128) {
    // Behind the last one: a reordered frame or a board reset. Resynchronize on it.
    last_ = seq;
    ++extended_;
    return Result::kOutOfOrder;
  }
  last_ = seq;
  extended_ += diff;
  if (diff == 1) {
    return Result::kInOrder;
  }
  last_gap_ = diff - 1U;
  return Result::kGap;
}

}  // namespace cleanslam::drivers::can_map
