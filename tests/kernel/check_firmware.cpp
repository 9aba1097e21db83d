// The complete cleanslam in the guest: on vcan0 (a simulated base board: gyro 100 Hz, encoders
// 20 Hz), the PL061 lift line, vivid's camera and the status LED on PL061 line 0, for a few
// seconds; it must keep running, send pose frames, see the lift, drive the LED from its health
// (read back from the kernel's /sys/kernel/debug/gpio) and stop cleanly on SIGTERM.
#include <fcntl.h>
#include <linux/can.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "cleanslam/drivers/can_messages.hpp"
#include "kernel_check.hpp"

namespace {

using cleanslam::kernel_test::Check;
namespace can_map = cleanslam::drivers::can_map;
using TimeNs = long long;

TimeNs now_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<TimeNs>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

int can_socket() {
  const int s = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  sockaddr_can a{};
  a.can_family = AF_CAN;
  a.can_ifindex = static_cast<int>(::if_nametoindex("vcan0"));
  ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
  return s;
}

void send(int s, const can_map::Frame& f) {
  can_frame c{};
  c.can_id = f.id;
  c.len = f.length;
  std::memcpy(c.data, f.data.data(), 8);
  (void)!::write(s, &c, sizeof c);
}

// The base board: 0.2 m/s forward with a slow left turn; silent while `quiet`.
void base_board(std::atomic<bool>* stop, std::atomic<bool>* quiet) {
  const int s = can_socket();
  TimeNs next = now_ns();
  for (int k = 0; !stop->load(); ++k) {
    const auto seq = static_cast<std::uint8_t>(k);
    if (quiet->load()) {
      next += 10'000'000;
      timespec ts{static_cast<time_t>(next / 1'000'000'000),
                  static_cast<long>(next % 1'000'000'000)};
      ::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
      continue;
    }
    send(s, can_map::encode(can_map::GyroMessage{50'000, 3000, seq, 0}));
    if (k % 5 == 0) {
      const std::int32_t ticks = (k / 5) * 40;  // 0.2 m/s at 4000 ticks/m, 20 Hz
      send(s, can_map::encode(can_map::EncoderMessage{ticks, ticks + (k / 5) * 2,
                                                      static_cast<std::uint8_t>(k / 5), 0}));
    }
    next += 10'000'000;
    timespec ts{static_cast<time_t>(next / 1'000'000'000), static_cast<long>(next % 1'000'000'000)};
    ::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
  }
  ::close(s);
}

// The level the kernel reports for the status LED (our output line): 1, 0, or -1 when no line
// of ours is an output (not requested, or released).
int led_level() {
  std::ifstream in("/sys/kernel/debug/gpio");
  std::string line;
  while (std::getline(in, line)) {
    if (line.find("cleanslam") != std::string::npos && line.find(" out ") != std::string::npos) {
      return line.find(" out hi") != std::string::npos ? 1 : 0;
    }
  }
  return -1;
}

}  // namespace

int main() {
  Check check("firmware");
  if (::access("/program/cleanslam", X_OK) != 0) {
    check.expect(false, "/program/cleanslam not in the guest");
    return check.finish();
  }
  // This robot's calibration: the base board's 4000 ticks per metre, vivid's camera as the
  // sample's.
  std::ofstream("/tmp/robot.yaml") << "calibration:\n"
                                      "  camera: {fx: 280, fy: 280, cx: 159.5, cy: 119.5,\n"
                                      "    distortion: [0, 0, 0, 0],\n"
                                      "    T_body_cam: [0, 0, 1, 0.1, -1, 0, 0, 0, 0, -1, 0, 0.08,"
                                      " 0, 0, 0, 1]}\n"
                                      "  wheels: {ticks_per_meter_left: 4000, "
                                      "ticks_per_meter_right: 4000, wheel_base: 0.235}\n"
                                      "  gyro: {noise_density: 0.0005}\n";
  std::atomic<bool> stop{false};
  std::atomic<bool> quiet{false};
  std::thread board(base_board, &stop, &quiet);
  const int listener = can_socket();

  const pid_t pid = ::fork();
  if (pid == 0) {
    const int log = ::open("/tmp/cleanslam.log", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(log, 1);
    ::dup2(log, 2);
    ::setenv("LD_LIBRARY_PATH", "/lib/aarch64-linux-gnu", 1);
    const char* argv[] = {"/program/cleanslam",
                          "--config",
                          "/tmp/robot.yaml",
                          "--set",
                          "source.kind=drivers",
                          "--set",
                          "source.can_interface=vcan0",
                          "--set",
                          "source.camera_device=/dev/video0",
                          "--set",
                          "source.gpio_chip=/dev/gpiochip0",
                          "--set",
                          "source.lift_line=3",
                          "--set",
                          "sinks.can=true",
                          "--set",
                          "sinks.can_interface=vcan0",
                          "--set",
                          "sinks.tum=/tmp/cleanslam.tum",
                          "--set",
                          "robot.status_led_line=0",
                          nullptr};
    ::execv(argv[0], const_cast<char* const*>(argv));
    std::perror("execv");
    ::_exit(127);
  }

  const TimeNs start = now_ns();
  int pose_frames = 0;
  int lifted_frames = 0;
  bool lift_requested = false;
  bool exited_early = false;
  int status = 0;
  // The LED after the first second: absent, low, high samples; level changes while all is well
  // (1-3 s) and while the base board is silent (4-5.5 s: encoders silent, a fault). Under TCG
  // the firmware's iterations come late (a frame-pipeline step takes up to ~0.3 s emulated), so
  // the fault's 4 Hz blink shows as at least one dark spell, not as its exact rhythm.
  int led_samples[3] = {0, 0, 0};
  int led_changes_ok = 0;
  int led_changes_silent = 0;
  int led_last = -1;
  while (now_ns() - start < 6'500'000'000LL) {
    const TimeNs since = now_ns() - start;
    quiet = since > 4'000'000'000LL && since < 5'500'000'000LL;
    if (since > 1'000'000'000LL) {
      const int level = led_level();
      ++led_samples[level + 1];
      const bool change = led_last >= 0 && level >= 0 && level != led_last;
      led_changes_ok += change && since < 3'000'000'000LL ? 1 : 0;
      led_changes_silent += change && since > 4'000'000'000LL && since < 6'000'000'000LL ? 1 : 0;
      if (change) {
        std::printf("  firmware: LED %d at %.3f s\n", level, static_cast<double>(since) * 1e-9);
      }
      led_last = level;
    }
    if (!lift_requested && now_ns() - start > 3'000'000'000LL) {
      std::printf("KERNEL-REQUEST powerdown\n");
      std::fflush(stdout);
      lift_requested = true;
    }
    pollfd p{listener, POLLIN, 0};
    if (::poll(&p, 1, 50) > 0) {
      can_frame f{};
      if (::read(listener, &f, sizeof f) == sizeof f && f.can_id != can_map::kEncoderId &&
          f.can_id != can_map::kGyroId) {
        ++pose_frames;
        if (f.can_id == can_map::kPoseYawId && (f.data[7] & 0x10U) != 0) {
          ++lifted_frames;
        }
      }
    }
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      exited_early = true;
      break;
    }
  }
  check.expect(!exited_early, "cleanslam exited on its own after %.1f s (status 0x%x)",
               static_cast<double>(now_ns() - start) * 1e-9, static_cast<unsigned>(status));
  bool clean = false;
  if (!exited_early) {
    const TimeNs term = now_ns();
    ::kill(pid, SIGTERM);
    while (now_ns() - term < 5'000'000'000LL) {
      if (::waitpid(pid, &status, WNOHANG) == pid) {
        clean = WIFEXITED(status) && WEXITSTATUS(status) == 0;
        check.note("stopped %.2f s after SIGTERM, status 0x%x",
                   static_cast<double>(now_ns() - term) * 1e-9, static_cast<unsigned>(status));
        break;
      }
      ::usleep(20'000);
    }
    if (!clean && ::waitpid(pid, &status, WNOHANG) == 0) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      check.note("still running 5 s after SIGTERM: killed");
    }
  }
  const int led_after = led_level();
  stop = true;
  board.join();
  check.note(
      "status LED: %d samples high, %d low, %d absent; %d changes while well, %d while the base "
      "board was silent",
      led_samples[2], led_samples[1], led_samples[0], led_changes_ok, led_changes_silent);
  check.expect(led_samples[0] == 0, "the status LED line was not an output of cleanslam");
  check.expect(led_samples[2] > 0, "the status LED was never lit");
  check.expect(led_changes_ok == 0, "the LED blinked while everything arrived");
  check.expect(led_changes_silent >= 2, "the LED did not blink while the base board was silent");
  check.expect(led_after != 1, "the status LED stayed lit after cleanslam stopped");
  check.expect(clean, "cleanslam did not stop cleanly on SIGTERM");
  {
    std::ifstream log("/tmp/cleanslam.log");
    bool uncalibrated = false;
    for (std::string line; std::getline(log, line);) {
      uncalibrated = uncalibrated || line.find("uncalibrated") != std::string::npos;
    }
    check.expect(!uncalibrated, "cleanslam called the calibrated robot uncalibrated");
  }
  check.note("%d pose frames on vcan0, %d of them flagged lifted", pose_frames, lifted_frames);
  check.expect(pose_frames >= 10, "only %d pose frames on vcan0", pose_frames);
  check.expect(lifted_frames > 0, "no pose frame flagged the lift (power-button pulse on line 3)");

  std::printf("  firmware: last lines of its log:\n");
  std::fflush(stdout);
  (void)!std::system("tail -n 15 /tmp/cleanslam.log | sed 's/^/    | /'");
  return check.finish();
}
