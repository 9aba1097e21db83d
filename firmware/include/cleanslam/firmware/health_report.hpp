#pragma once

#include <array>
#include <cstdint>
#include <cstdio>

#include "cleanslam/firmware/health.hpp"

namespace cleanslam::firmware {

// The health report on stderr: one line per flag raised or cleared ("t=12.300 s: gyro silent
// (heading from encoders)"), and per silent source the first time it fell silent, how often and
// for how long in all, so a caller can tell a run with a sensor gap from a clean one.
class HealthReport final : public HealthObserver {
 public:
  enum Source : std::uint8_t { kGyro, kEncoders, kCamera, kSourceCount };
  struct Silence {
    int episodes = 0;
    std::int64_t first_ns = -1;
    std::int64_t total_ns = 0;
    std::int64_t since_ns = -1;  // silent now, since then; -1: not silent
  };

  HealthReport(const char* program, std::FILE* out) : program_(program), out_(out) {}
  void health_changed(std::int64_t t_ns, std::uint32_t before, std::uint32_t after) override;
  // The first refusal of each reason, in words; later ones are counted in the summary.
  void first_reject(std::int64_t t_ns, Reject r) override;
  // Closes the silences still open at `end_ns` (the run's last time).
  void finish(std::int64_t end_ns);
  [[nodiscard]] const Silence& silence(Source s) const { return silences_[s]; }
  [[nodiscard]] static const char* source_name(Source s);

 private:
  const char* program_;
  std::FILE* out_;
  std::array<Silence, kSourceCount> silences_{};
};

}  // namespace cleanslam::firmware
