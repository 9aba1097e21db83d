#pragma once

#include <cstdint>

#include "cleanslam/drivers/status_led.hpp"
#include "cleanslam/firmware/run.hpp"

namespace cleanslam::firmware {

// The loop's health (hal::HealthFlag) as an LED pattern: fault when the pose is not known (lifted,
// relocalizing, its std. dev. beyond the threshold), degraded when it rests on fewer sensors than
// planned (gyro, encoders or camera silent, few landmarks, a configured device missing, the
// calibration not set), else OK.
[[nodiscard]] drivers::LedPattern led_pattern(std::uint32_t health, bool set_up_incomplete);

// Drives the status LED from the live runner after each loop iteration; never blocks (one GPIO
// write when the level changes) and asks to run again at the pattern's next level change.
class StatusIndicator final : public LiveTask {
 public:
  explicit StatusIndicator(drivers::StatusLed& led, bool set_up_incomplete = false)
      : led_(led), set_up_incomplete_(set_up_incomplete) {}

  void run(const Loop& loop, hal::TimeNs now) override { show(loop.health(), now); }
  void show(std::uint32_t health, hal::TimeNs now) {
    led_.set_pattern(led_pattern(health, set_up_incomplete_), now);
  }
  [[nodiscard]] hal::TimeNs next_due_ns() const override { return led_.next_change_ns(); }

 private:
  drivers::StatusLed& led_;
  bool set_up_incomplete_;
};

}  // namespace cleanslam::firmware
