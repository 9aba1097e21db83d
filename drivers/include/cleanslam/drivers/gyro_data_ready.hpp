#pragma once

#include <array>
#include <cstdint>

#include "cleanslam/drivers/can_base_board.hpp"
#include "cleanslam/drivers/diagnostics.hpp"
#include "cleanslam/drivers/gpio_api.hpp"
#include "cleanslam/drivers/gpio_line.hpp"
#include "cleanslam/drivers/os.hpp"

namespace cleanslam::drivers {

struct GyroDataReadyConfig {
  GpioLineConfig gpio;  // rising edge = a gyro sample was taken
  // A CAN gyro frame belongs to the latest edge at most this long before its reception.
  hal::TimeNs max_latency_ns = 8 * hal::kNsPerMillisecond;
};

struct GyroDataReadyStats {
  std::uint64_t edges = 0;
  std::uint64_t matched = 0;
  std::uint64_t unmatched = 0;  // no edge close enough: the CAN reception time was kept
};

// The optional gyro data-ready input: each gyro frame gets the time of the rising edge that
// preceded its reception, instead of the CAN reception time (bus and queueing latency removed).
// Without a matching edge the reception time stays; the start and end of such an outage are
// reported once each.
class GyroDataReady final : public GyroTimeReference {
 public:
  GyroDataReady(const GyroDataReadyConfig& config, GpioApi& api = libgpiod_api(),
                Os& os = linux_os(), Diagnostics& diagnostics = stderr_diagnostics());

  bool sample_time(hal::TimeNs received_ns, hal::TimeNs& sample_ns) override;
  [[nodiscard]] bool available() const { return line_.available(); }
  [[nodiscard]] const GyroDataReadyStats& stats() const { return stats_; }

 private:
  void drain();

  GyroDataReadyConfig config_;
  GpioApi& api_;
  Os& os_;
  Diagnostics& diagnostics_;
  bool missing_ = false;  // the last frame had no edge (reported once per outage)
  GpioLine line_;
  int event_fd_ = -1;
  static constexpr std::size_t kRing = 16;
  std::array<hal::TimeNs, kRing> edges_{};
  std::size_t head_ = 0;   // next write
  std::size_t count_ = 0;  // unconsumed edges, oldest at head_ - count_
  GyroDataReadyStats stats_;
};

}  // namespace cleanslam::drivers
