#pragma once

#include <cstdint>

#include "cleanslam/hal/frame.hpp"
#include "cleanslam/hal/pose.hpp"
#include "cleanslam/hal/samples.hpp"
#include "cleanslam/hal/time.hpp"

namespace cleanslam::hal {

// The loop's clock: the monotonic clock on the robot, a virtual clock in replay.
class Clock {
 public:
  virtual ~Clock() = default;
  [[nodiscard]] virtual TimeNs now() const = 0;
};

// What a source hands the loop: one sample or frame.
struct SensorEvent {
  enum class Kind : std::uint8_t { kNone, kGyro, kEncoder, kFrame, kLift };
  Kind kind = Kind::kNone;
  GyroSample gyro;
  EncoderSample encoder;
  CameraFrame frame;  // views valid until the same source's next call
  bool lifted = false;
};

// A source of sensor events. Real sources expose a file descriptor for poll(); virtual-time
// sources (replay) return -1 and say when their next event is due.
class SensorSource {
 public:
  virtual ~SensorSource() = default;
  // Descriptor to wait on with poll(), or -1.
  [[nodiscard]] virtual int fd() const { return -1; }
  // Time of the next event on the source's clock, or -1 when unknown (real devices) or at end.
  [[nodiscard]] virtual TimeNs next_event_time() const { return -1; }
  // Non-blocking: fills `out` and returns true when an event is ready.
  virtual bool read(SensorEvent& out) = 0;
  // True when the source will never produce another event (end of a dataset or log).
  [[nodiscard]] virtual bool exhausted() const { return false; }
};

class PoseSink {
 public:
  virtual ~PoseSink() = default;
  virtual void publish(const PoseEstimate& pose) = 0;
  virtual void flush() {}
};

}  // namespace cleanslam::hal
