#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "cleanslam/drivers/diagnostics.hpp"
#include "cleanslam/drivers/luma.hpp"
#include "cleanslam/drivers/os.hpp"
#include "cleanslam/drivers/readiness.hpp"
#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/interfaces.hpp"

namespace cleanslam::drivers {

struct V4l2CameraConfig {
  std::string device = "/dev/video0";
  // Frames handed to the loop per second (the paper's camera: 1-2 Hz); the rest are dropped.
  double rate_hz = 2.0;
  // Frame rate asked of the device; it gives the nearest it has.
  double device_fps = 5.0;
  // "auto" (GREY, else YUYV), "GREY" or "YUYV".
  std::string pixel_format = "auto";
  int buffers = 4;  // memory-mapped, at least 2
  // Largest integer reduction accepted (e.g. 2: 640x480 -> 320x240).
  int max_scale = 4;
  hal::TimeNs reopen_min_ns = 250 * hal::kNsPerMillisecond;
  hal::TimeNs reopen_max_ns = 5 * hal::kNsPerSecond;
};

struct V4l2CameraStats {
  std::uint64_t dequeued = 0;
  std::uint64_t delivered = 0;
  std::uint64_t dropped_rate = 0;    // beyond the configured rate
  std::uint64_t dropped_error = 0;   // buffer flagged as corrupt, or too short
  std::uint64_t device_dropped = 0;  // gaps in the driver's sequence numbers
  std::uint64_t opens = 0;
  std::uint64_t open_failures = 0;
  std::uint64_t stream_errors = 0;  // EIO, vanished device
  std::uint64_t future_stamps = 0;  // driver stamps later than the dequeue, clamped to it
};

// What the negotiation settled on.
struct V4l2Format {
  std::uint32_t fourcc = 0;
  int width = 0;
  int height = 0;
  int stride = 0;
  int scale = 1;
  double fps = 0.0;  // 0 when the device does not say
};

// A V4L2 capture device as a SensorSource of 320x240 gray frames at the configured rate.
class V4l2Camera final : public hal::SensorSource {
 public:
  explicit V4l2Camera(V4l2CameraConfig config, Os& os = linux_os(),
                      Diagnostics& diagnostics = stderr_diagnostics());
  ~V4l2Camera() override;
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  // Stable across reopens: readable when a buffer is ready or a reopen is due.
  [[nodiscard]] int fd() const override { return readiness_.fd(); }
  bool read(hal::SensorEvent& out) override;

  [[nodiscard]] bool streaming() const { return streaming_; }
  [[nodiscard]] const V4l2Format& format() const { return format_; }
  [[nodiscard]] const V4l2CameraStats& stats() const { return stats_; }

 private:
  struct Buffer {
    void* data = nullptr;
    std::size_t length = 0;
  };

  bool open_device();
  bool negotiate();
  bool start_streaming();
  void close_device();
  void fail_and_reopen(const char* what, int error);
  bool accept_frame(hal::TimeNs t_ns);

  V4l2CameraConfig config_;
  Os& os_;
  Diagnostics& diagnostics_;
  Readiness readiness_;
  Backoff backoff_;
  int fd_ = -1;
  bool streaming_ = false;
  bool warned_timestamps_ = false;
  V4l2Format format_;
  V4l2CameraStats stats_;
  std::vector<Buffer> buffers_;
  std::vector<std::uint8_t> image_;
  std::uint32_t seq_ = 0;
  std::uint32_t last_device_seq_ = 0;
  bool has_device_seq_ = false;
  bool has_delivered_ = false;
  hal::TimeNs next_due_ns_ = 0;
};

// "GREY", "YUYV", ... of a V4L2 fourcc.
std::string fourcc_name(std::uint32_t fourcc);

}  // namespace cleanslam::drivers
