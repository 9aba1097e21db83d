#include "cleanslam/drivers/status_led.hpp"

namespace cleanslam::drivers {
namespace {

hal::TimeNs half_period(LedPattern pattern) {
  switch (pattern) {
    case LedPattern::kDegraded:
      return 500 * hal::kNsPerMillisecond;
    case LedPattern::kFault:
      return 125 * hal::kNsPerMillisecond;
    case LedPattern::kOff:
    case LedPattern::kOk:
      return 0;
  }
  return 0;
}

}  // namespace

int led_level(LedPattern pattern, hal::TimeNs t_ns) {
  const hal::TimeNs half = half_period(pattern);
  if (half == 0) {
    return pattern == LedPattern::kOk ? 1 : 0;
  }
  return ((t_ns < 0 ? 0 : t_ns) / half) % 2 == 0 ? 1 : 0;
}

hal::TimeNs led_next_change(LedPattern pattern, hal::TimeNs t_ns) {
  const hal::TimeNs half = half_period(pattern);
  if (half == 0) {
    return -1;
  }
  const hal::TimeNs t = t_ns < 0 ? 0 : t_ns;
  return (t / half + 1) * half;
}

StatusLed::StatusLed(const GpioLineConfig& config, GpioApi& api, Diagnostics& diagnostics)
    : api_(api), line_(api, diagnostics, "led", config, "status LED", GpioLine::Mode::kOutput, 0) {}

StatusLed::~StatusLed() {
  if (line_.available()) {
    api_.set_value(line_.handle(), 0);
  }
}

void StatusLed::set_pattern(LedPattern pattern, hal::TimeNs now_ns) {
  if (pattern == pattern_ && next_ns_ >= 0) {
    update(now_ns);
    return;
  }
  pattern_ = pattern;
  start_ns_ = now_ns;
  level_ = -1;
  update(now_ns);
}

void StatusLed::update(hal::TimeNs now_ns) {
  const hal::TimeNs t = now_ns - start_ns_;
  const int level = led_level(pattern_, t);
  const hal::TimeNs next = led_next_change(pattern_, t);
  next_ns_ = next < 0 ? -1 : start_ns_ + next;
  if (level != level_) {
    level_ = level;
    if (line_.available()) {
      api_.set_value(line_.handle(), level);
    }
  }
}

}  // namespace cleanslam::drivers
