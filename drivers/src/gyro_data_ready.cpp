#include "cleanslam/drivers/gyro_data_ready.hpp"

namespace cleanslam::drivers {

GyroDataReady::GyroDataReady(const GyroDataReadyConfig& config, GpioApi& api, Os& os,
                             Diagnostics& diagnostics)
    : config_(config),
      api_(api),
      os_(os),
      diagnostics_(diagnostics),
      line_(api, diagnostics, "gyro-drdy", config.gpio, "gyro data-ready input",
            GpioLine::Mode::kRisingEdge) {
  event_fd_ = line_.event_fd();
}

void GyroDataReady::drain() {
  while (event_fd_ >= 0 && os_.poll_readable(event_fd_, 0)) {
    GpioEdge edge;
    if (api_.read_edge(line_.handle(), edge) < 0) {
      return;
    }
    if (!edge.rising) {
      continue;
    }
    ++stats_.edges;
    edges_[head_] = edge.t_ns;
    head_ = (head_ + 1) % kRing;
    count_ = count_ < kRing ? count_ + 1 : kRing;
  }
}

bool GyroDataReady::sample_time(hal::TimeNs received_ns, hal::TimeNs& sample_ns) {
  if (!line_.available()) {
    return false;
  }
  drain();
  // Oldest first: edges too old for this frame are dropped, the first one in the window is used.
  while (count_ > 0) {
    const std::size_t oldest = (head_ + kRing - count_) % kRing;
    const hal::TimeNs t = edges_[oldest];
    if (t > received_ns) {
      break;
    }
    --count_;
    if (received_ns - t <= config_.max_latency_ns) {
      sample_ns = t;
      ++stats_.matched;
      if (missing_) {
        missing_ = false;
        reportf(diagnostics_, Severity::kInfo, "gyro-drdy",
                "data-ready edges are back: gyro samples take the edge time again (%llu frames "
                "without an edge so far)",
                static_cast<unsigned long long>(stats_.unmatched));
      }
      return true;
    }
  }
  ++stats_.unmatched;
  if (!missing_) {
    missing_ = true;
    reportf(diagnostics_, Severity::kWarning, "gyro-drdy",
            "no data-ready edge within %.1f ms before the gyro frame received at %.3f s: using "
            "the CAN reception time until edges return",
            hal::to_seconds(config_.max_latency_ns) * 1e3, hal::to_seconds(received_ns));
  }
  return false;
}

}  // namespace cleanslam::drivers
