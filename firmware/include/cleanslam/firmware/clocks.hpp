#pragma once

#include "cleanslam/hal/interfaces.hpp"

namespace cleanslam::firmware {

// CLOCK_MONOTONIC, the clock the drivers stamp samples with.
class MonotonicClock final : public hal::Clock {
 public:
  [[nodiscard]] hal::TimeNs now() const override;
};

// Replay and simulation: time moves only when the runner sets it.
class VirtualClock final : public hal::Clock {
 public:
  [[nodiscard]] hal::TimeNs now() const override { return now_; }
  void set(hal::TimeNs t) { now_ = t; }

 private:
  hal::TimeNs now_ = 0;
};

}  // namespace cleanslam::firmware
