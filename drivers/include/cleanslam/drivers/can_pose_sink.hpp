#pragma once

#include <cstdint>
#include <string>

#include "cleanslam/drivers/diagnostics.hpp"
#include "cleanslam/drivers/os.hpp"
#include "cleanslam/drivers/readiness.hpp"
#include "cleanslam/hal/interfaces.hpp"

namespace cleanslam::drivers {

struct CanPoseSinkStats {
  std::uint64_t published = 0;
  std::uint64_t frames_sent = 0;
  std::uint64_t frames_dropped = 0;  // transmit queue full, bus-off, interface gone
  std::uint64_t open_failures = 0;
};

// Sends each estimate as the pose frames of docs/can.md (0x201 position, 0x202 yaw and quality)
// on a raw socket. Never blocks: a full transmit queue drops the frame and counts it.
class CanPoseSink final : public hal::PoseSink {
 public:
  explicit CanPoseSink(std::string interface, Os& os = linux_os(),
                       Diagnostics& diagnostics = stderr_diagnostics());
  ~CanPoseSink() override;
  CanPoseSink(const CanPoseSink&) = delete;
  CanPoseSink& operator=(const CanPoseSink&) = delete;

  void publish(const hal::PoseEstimate& pose) override;
  [[nodiscard]] const CanPoseSinkStats& stats() const { return stats_; }
  [[nodiscard]] bool connected() const { return socket_ >= 0; }

 private:
  bool open_socket();
  bool send(std::uint32_t id, const std::uint8_t* data);

  std::string interface_;
  Os& os_;
  Diagnostics& diagnostics_;
  int socket_ = -1;
  std::uint8_t seq_ = 0;
  hal::TimeNs retry_at_ns_ = 0;
  Backoff backoff_{100 * hal::kNsPerMillisecond, 5 * hal::kNsPerSecond};
  RateLimit drop_limit_{10 * hal::kNsPerSecond};
  CanPoseSinkStats stats_;
};

}  // namespace cleanslam::drivers
