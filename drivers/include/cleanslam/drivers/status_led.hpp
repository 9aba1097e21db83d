#pragma once

#include <cstdint>

#include "cleanslam/drivers/diagnostics.hpp"
#include "cleanslam/drivers/gpio_api.hpp"
#include "cleanslam/drivers/gpio_line.hpp"
#include "cleanslam/hal/time.hpp"

namespace cleanslam::drivers {

// OK: steady on. Degraded: 1 Hz, half on. Fault: 4 Hz, half on. Off: off.
enum class LedPattern : std::uint8_t { kOff, kOk, kDegraded, kFault };

// Level of `pattern` at `t_ns` since the pattern started.
[[nodiscard]] int led_level(LedPattern pattern, hal::TimeNs t_ns);
// Time after `t_ns` (since the pattern started) at which the level changes next, or -1.
[[nodiscard]] hal::TimeNs led_next_change(LedPattern pattern, hal::TimeNs t_ns);

// The status LED on a GPIO output. The loop calls update() at next_change_ns() (or any time).
class StatusLed {
 public:
  StatusLed(const GpioLineConfig& config, GpioApi& api = libgpiod_api(),
            Diagnostics& diagnostics = stderr_diagnostics());
  ~StatusLed();
  StatusLed(const StatusLed&) = delete;
  StatusLed& operator=(const StatusLed&) = delete;

  void set_pattern(LedPattern pattern, hal::TimeNs now_ns);
  void update(hal::TimeNs now_ns);
  // When update() must run next, or -1 while the level is steady.
  [[nodiscard]] hal::TimeNs next_change_ns() const { return next_ns_; }
  [[nodiscard]] bool available() const { return line_.available(); }
  [[nodiscard]] LedPattern pattern() const { return pattern_; }
  [[nodiscard]] int level() const { return level_; }

 private:
  GpioApi& api_;
  GpioLine line_;
  LedPattern pattern_ = LedPattern::kOff;
  hal::TimeNs start_ns_ = 0;
  hal::TimeNs next_ns_ = -1;
  int level_ = 0;
};

}  // namespace cleanslam::drivers
