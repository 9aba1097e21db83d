// Real-kernel check of the libgpiod lines on the virt board's PL061: the power button pulse of
// QEMU's system_powerdown on line 3 arrives as a lift and a set-down; missing chips and lines are
// explained; the status LED drives its output; a data-ready edge time-stamps the CAN gyro frame
// that follows it.
#include <linux/can.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cleanslam/drivers/can_base_board.hpp"
#include "cleanslam/drivers/can_messages.hpp"
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

int vcan_sender() {
  const int s = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  sockaddr_can a{};
  a.can_family = AF_CAN;
  a.can_ifindex = static_cast<int>(::if_nametoindex("vcan0"));
  if (s >= 0 && ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(s);
    return -1;
  }
  return s;
}

// The whole path: gyro frames on vcan0 read by the base-board driver, which asks the data-ready
// line for their sample time. Frames before and after the power-button edge keep their CAN
// reception time; the first one after the edge takes the edge's kernel time.
bool check_data_ready() {
  Check check("gpio_data_ready");
  Collected diag;
  drivers::GyroDataReadyConfig config;
  config.gpio.line = "3";
  config.max_latency_ns = 2'000'000'000;
  drivers::GyroDataReady drdy(config, drivers::libgpiod_api(), drivers::linux_os(), diag);
  drivers::CanBaseBoardConfig board_config;
  board_config.interface = "vcan0";
  drivers::CanBaseBoard board(board_config, drivers::linux_os(), diag);
  board.set_gyro_time_reference(&drdy);
  const int sender = vcan_sender();
  if (!check.expect(drdy.available(), "line 3 not available for data-ready") ||
      !check.expect(board.connected() && sender >= 0, "vcan0 not usable")) {
    return check.finish() == 0;
  }
  const TimeNs asked = now_ns();
  request_power_button();
  TimeNs edge_t = -1;
  TimeNs last_t = -1;
  int before = 0;
  int after = 0;
  bool in_order = true;
  bool stamps_in_window = true;
  std::deque<TimeNs> unread_sends;
  for (int seq = 0; now_ns() < asked + 8'000'000'000 && after < 5; ++seq) {
    const auto f = drivers::can_map::encode(
        drivers::can_map::GyroMessage{10'000, 2500, static_cast<std::uint8_t>(seq), 0});
    can_frame c{};
    c.can_id = f.id;
    c.len = f.length;
    std::memcpy(c.data, f.data.data(), 8);
    unread_sends.push_back(now_ns());
    (void)!::write(sender, &c, sizeof c);
    const timespec pause{0, 20'000'000};
    ::nanosleep(&pause, nullptr);
    const std::uint64_t matched = drdy.stats().matched;
    SensorEvent e;
    while (board.read(e)) {
      if (e.kind != SensorEvent::Kind::kGyro) {
        continue;
      }
      // Frames arrive in the order sent; on a loaded host one may come after the next is sent.
      const TimeNs sent = unread_sends.empty() ? asked : unread_sends.front();
      if (!unread_sends.empty()) {
        unread_sends.pop_front();
      }
      in_order = in_order && e.gyro.t_ns > last_t;
      last_t = e.gyro.t_ns;
      if (drdy.stats().matched > matched && edge_t < 0) {
        edge_t = e.gyro.t_ns;
        stamps_in_window = stamps_in_window && edge_t > asked && edge_t <= now_ns();
      } else {
        // The CAN reception time: between sending and now (1 ms for the clock conversion).
        stamps_in_window =
            stamps_in_window && e.gyro.t_ns >= sent - 1'000'000 && e.gyro.t_ns <= now_ns();
        (edge_t < 0 ? before : after)++;
      }
    }
  }
  ::close(sender);
  check.expect(edge_t >= 0, "no gyro frame took a data-ready edge's time");
  check.expect(drdy.stats().matched == 1, "%llu frames matched an edge, expected 1",
               static_cast<unsigned long long>(drdy.stats().matched));
  check.expect(after >= 5, "%d frames on CAN time after the edge, expected 5", after);
  check.expect(in_order, "gyro sample times not increasing");
  check.expect(stamps_in_window, "a sample time outside its window (edge or CAN reception)");
  check.expect(diag.has("no data-ready edge"), "the missing edges were not reported");
  check.note("edge %.1f ms after the request; %d frames on CAN time before, %d after",
             static_cast<double>(edge_t - asked) * 1e-6, before, after);
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
