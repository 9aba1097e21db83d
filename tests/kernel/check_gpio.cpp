// Real-kernel check of the libgpiod lines on the virt board's PL061: the power button pulse of
// QEMU's system_powerdown on line 3 arrives as a lift and a set-down; missing chips and lines are
// explained; the status LED drives its output; data-ready edges time-stamp gyro samples.
#include <poll.h>
#include <time.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cleanslam/drivers/diagnostics.hpp"
#include "cleanslam/drivers/gyro_data_ready.hpp"
#include "cleanslam/drivers/lift_switch.hpp"
#include "cleanslam/drivers/status_led.hpp"
#include "kernel_check.hpp"

namespace {

using cleanslam::hal::SensorEvent;
using cleanslam::hal::TimeNs;
using cleanslam::kernel_test::Check;
namespace drivers = cleanslam::drivers;

TimeNs now_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<TimeNs>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

class Collected : public drivers::Diagnostics {
 public:
  std::string text;
  void report(drivers::Severity, std::string_view component, std::string_view message) override {
    text += std::string(component) + ": " + std::string(message) + "\n";
    std::printf("    diagnostics %.*s: %.*s\n", static_cast<int>(component.size()),
                component.data(), static_cast<int>(message.size()), message.data());
  }
  [[nodiscard]] bool has(const std::string& s) const { return text.find(s) != std::string::npos; }
};

void request_power_button() {
  std::printf("KERNEL-REQUEST powerdown\n");
  std::fflush(stdout);
}

bool check_lift() {
  Check check("gpio_lift");
  drivers::LiftSwitchConfig config;
  config.gpio.chip = "gpiochip0";
  config.gpio.line = "3";
  drivers::LiftSwitch lift(config);
  if (!check.expect(lift.available(), "line 3 of gpiochip0 not available")) {
    return check.finish() == 0;
  }
  request_power_button();
  std::vector<bool> states;
  std::vector<TimeNs> times;
  const TimeNs deadline = now_ns() + 8'000'000'000;
  while (now_ns() < deadline && states.size() < 2) {
    pollfd p{lift.fd(), POLLIN, 0};
    ::poll(&p, 1, 50);
    SensorEvent e;
    while (lift.read(e)) {
      check.expect(e.kind == SensorEvent::Kind::kLift, "event kind %d", static_cast<int>(e.kind));
      states.push_back(e.lifted);
      times.push_back(now_ns());
    }
  }
  check.expect(states.size() == 2, "%zu lift events, expected 2 (lifted, set down)", states.size());
  if (states.size() == 2) {
    check.expect(states[0] && !states[1], "events in the wrong order");
    check.note("lifted, then set down %.0f ms later (QEMU's pulse is 100 ms)",
               static_cast<double>(times[1] - times[0]) * 1e-6);
  }
  check.note("edges %llu, bounces %llu", static_cast<unsigned long long>(lift.stats().edges),
             static_cast<unsigned long long>(lift.stats().bounces));
  return check.finish() == 0;
}

bool check_missing() {
  Check check("gpio_missing");
  Collected diag;
  drivers::LiftSwitchConfig config;
  config.gpio.chip = "gpiochip7";
  config.gpio.line = "3";
  drivers::LiftSwitch no_chip(config, drivers::libgpiod_api(), drivers::linux_os(), diag);
  config.gpio.chip = "gpiochip0";
  config.gpio.line = "WHEEL_DROP";
  drivers::LiftSwitch no_line(config, drivers::libgpiod_api(), drivers::linux_os(), diag);
  SensorEvent e;
  check.expect(!no_chip.available() && !no_chip.read(e), "missing chip reported available");
  check.expect(!no_line.available() && !no_line.read(e), "missing line reported available");
  check.expect(diag.has("GPIO chip 'gpiochip7' for the lift switch not found"),
               "no message for the missing chip");
  check.expect(diag.has("chips present: gpiochip0 ["), "message does not list gpiochip0");
  check.expect(
      diag.has("GPIO line 'WHEEL_DROP' for the lift switch not found on chip 'gpiochip0' (8 lines"),
      "no message for the missing line");
  return check.finish() == 0;
}

std::string debugfs_gpio() {
  std::ifstream in("/sys/kernel/debug/gpio");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The state the kernel reports for our line: "out hi" or "out lo".
std::string led_state() {
  std::istringstream lines(debugfs_gpio());
  std::string line;
  while (std::getline(lines, line)) {
    if (line.find("cleanslam") != std::string::npos) {
      return line.find("out hi") != std::string::npos   ? "hi"
             : line.find("out lo") != std::string::npos ? "lo"
                                                        : line;
    }
  }
  return "absent";
}

bool check_led() {
  Check check("gpio_led");
  drivers::GpioLineConfig config;
  config.line = "0";
  drivers::StatusLed led(config);
  if (!check.expect(led.available(), "line 0 of gpiochip0 not available as output")) {
    return check.finish() == 0;
  }
  const TimeNs t0 = now_ns();
  led.set_pattern(drivers::LedPattern::kOk, t0);
  check.expect(led_state() == "hi", "OK: kernel says '%s', expected hi", led_state().c_str());
  led.set_pattern(drivers::LedPattern::kFault, t0);
  led.update(t0 + 130'000'000);
  check.expect(led_state() == "lo", "fault at 130 ms: '%s', expected lo", led_state().c_str());
  led.update(t0 + 260'000'000);
  check.expect(led_state() == "hi", "fault at 260 ms: '%s', expected hi", led_state().c_str());
  led.set_pattern(drivers::LedPattern::kOff, t0);
  check.expect(led_state() == "lo", "off: '%s', expected lo", led_state().c_str());
  return check.finish() == 0;
}

bool check_data_ready() {
  Check check("gpio_data_ready");
  drivers::GyroDataReadyConfig config;
  config.gpio.line = "3";
  config.max_latency_ns = 2'000'000'000;
  drivers::GyroDataReady drdy(config);
  if (!check.expect(drdy.available(), "line 3 not available for data-ready")) {
    return check.finish() == 0;
  }
  const TimeNs asked = now_ns();
  request_power_button();
  TimeNs t = 0;
  bool matched = false;
  while (!matched && now_ns() < asked + 8'000'000'000) {
    struct timespec pause {
      0, 20'000'000
    };
    ::nanosleep(&pause, nullptr);
    matched = drdy.sample_time(now_ns(), t);
  }
  check.expect(matched, "no data-ready edge matched");
  check.expect(!matched || (t > asked && t <= now_ns()),
               "edge time not between the request and now (monotonic kernel stamps?)");
  check.note("edge %.1f ms after the request", static_cast<double>(t - asked) * 1e-6);
  return check.finish() == 0;
}

}  // namespace

int main() {
  bool ok = check_missing();
  ok = check_lift() && ok;
  ok = check_led() && ok;
  ok = check_data_ready() && ok;
  return ok ? 0 : 1;
}
