// The robot's wiring in the firmware: the robot.* keys, the status LED driven from the loop's
// health, and the set-down policy after a lift.
#include <gtest/gtest.h>
#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "../drivers/fake_gpio.hpp"
#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/firmware/program.hpp"
#include "cleanslam/firmware/run.hpp"
#include "cleanslam/firmware/slam_estimator.hpp"
#include "cleanslam/firmware/status_indicator.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/dataset_source.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"
#include "fakes.hpp"
#include "text_checks.hpp"

namespace cleanslam {
namespace {

namespace fs = std::filesystem;
using cleanslam::test::kMs;
using cleanslam::test::kS;
using drivers::LedPattern;
using firmware::FirmwareConfig;
using firmware::led_pattern;
using firmware::parse_config;
using firmware::RobotSettings;

using test::joined;

TEST(RobotConfig, SetDownPolicyAndLinesAreReadAndValidated) {
  const auto r = parse_config(
      "map_management:\n  on_set_down: relocalize\n  relocalize_std_m: 0.5\nrobot:\n"
      "  status_led_line: 4\n  gyro_ready_line: 7\n",
      "r.yaml", {});
  ASSERT_TRUE(r.ok()) << joined(r.errors);
  EXPECT_EQ(r.config.slam.map.on_set_down, slam_core::MapConfig::SetDown::kRelocalize);
  EXPECT_EQ(r.config.slam.map.relocalize_std_m, 0.5);
  EXPECT_EQ(r.config.robot.status_led_line, 4);
  EXPECT_EQ(r.config.robot.gyro_ready_line, 7);
  EXPECT_EQ(FirmwareConfig{}.slam.map.on_set_down, slam_core::MapConfig::SetDown::kRelocalize);
  const auto back = parse_config(firmware::config_text(r.config), "back", {});
  ASSERT_TRUE(back.ok()) << joined(back.errors);
  EXPECT_EQ(back.config.slam.map.on_set_down, slam_core::MapConfig::SetDown::kRelocalize);

  const auto bad = parse_config(
      "map_management:\n  on_set_down: teleport\n  relocalize_std_yaw_deg: 400\nrobot:\n"
      "  status_led_line: -2\n",
      "bad.yaml", {"robot.gyro_ready_line=2000"});
  ASSERT_EQ(bad.errors.size(), 4U) << joined(bad.errors);
  const std::string all = joined(bad.errors);
  EXPECT_NE(all.find("bad.yaml:2: map_management.on_set_down: \"teleport\" is not one of new_map, "
                     "relocalize"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("bad.yaml:3: map_management.relocalize_std_yaw_deg"), std::string::npos)
      << all;
  EXPECT_NE(all.find("bad.yaml:5: robot.status_led_line"), std::string::npos) << all;
  EXPECT_NE(all.find("robot.gyro_ready_line: 2000 is out of range"), std::string::npos) << all;
}

TEST(StatusIndicator, HealthMapsToPatterns) {
  EXPECT_EQ(led_pattern(hal::kHealthOk, false), LedPattern::kOk);
  EXPECT_EQ(led_pattern(hal::kStandingStill, false), LedPattern::kOk);
  EXPECT_EQ(led_pattern(hal::kHealthOk, true), LedPattern::kDegraded);
  EXPECT_EQ(led_pattern(hal::kGyroSilent, false), LedPattern::kDegraded);
  EXPECT_EQ(led_pattern(hal::kCameraSilent | hal::kStandingStill, false), LedPattern::kDegraded);
  EXPECT_EQ(led_pattern(hal::kEncodersSilent, false), LedPattern::kDegraded);
  EXPECT_EQ(led_pattern(hal::kLifted | hal::kPoseLost, false), LedPattern::kFault);
  EXPECT_EQ(led_pattern(hal::kPoseLost | hal::kGyroSilent, true), LedPattern::kFault);
}

// The loop on a scripted robot, the LED on a fake GPIO line: OK while everything arrives,
// slow blink while the camera is silent, fast blink while the encoders are, off at the end.
TEST(StatusIndicator, FollowsTheLoopHealthOnAFakeLine) {
  drivers::testing::FakeOs os;
  drivers::testing::FakeGpio gpio(os);
  drivers::testing::RecordingDiagnostics diag;
  drivers::GpioLineConfig lc;
  lc.line = "1";
  auto led = std::make_unique<drivers::StatusLed>(lc, gpio, diag);
  ASSERT_TRUE(led->available()) << diag.all();
  const auto& line = gpio.line("gpiochip0", 1);

  test::ScriptedSource src;
  // 0-2 s everything; from 2 s no camera (silent after 3 s more); from 10 s no encoders and the
  // pose lost.
  src.drive(0, 12 * kS, 2.0, [&](hal::SensorEvent::Kind k, hal::TimeNs t) {
    return (k == hal::SensorEvent::Kind::kFrame && t >= 2 * kS) ||
           (k == hal::SensorEvent::Kind::kEncoder && t >= 10 * kS);
  });
  test::FakeEstimator est;
  firmware::Loop loop(firmware::LoopOptions{}, est);
  loop.add_source(&src);
  firmware::StatusIndicator indicator(*led);
  loop.start(0);
  indicator.run(loop, 0);
  // Every 10 ms (the loop's and the LED's deadlines fall on that grid): the level, per window.
  struct Window {
    hal::TimeNs from, to;
    int high = 0, low = 0, changes = 0;
  };
  std::vector<Window> windows{
      {1 * kS, 4900 * kMs}, {5500 * kMs, 9500 * kMs}, {10500 * kMs, 12 * kS}};
  int last = -1;
  for (hal::TimeNs t = 10 * kMs; t < 12 * kS; t += 10 * kMs) {
    est.lost = t >= 10 * kS;
    loop.iterate(t);
    indicator.run(loop, t);
    EXPECT_TRUE(indicator.next_due_ns() < 0 || indicator.next_due_ns() > t) << t;
    for (auto& w : windows) {
      if (t >= w.from && t < w.to) {
        (line.value != 0 ? w.high : w.low)++;
        w.changes += last >= 0 && line.value != last ? 1 : 0;
      }
    }
    last = line.value;
  }
  EXPECT_EQ(windows[0].low, 0);  // OK: steady on
  EXPECT_EQ(windows[0].changes, 0);
  // Degraded: 1 Hz, half on: 4 s give 8 changes (+-1 at the window's ends).
  EXPECT_NEAR(windows[1].changes, 8, 1);
  EXPECT_NEAR(windows[1].high, windows[1].low, 10);
  // Fault: 4 Hz: 1.5 s give 12 changes.
  EXPECT_NEAR(windows[2].changes, 12, 1);
  EXPECT_EQ(loop.health() & (hal::kEncodersSilent | hal::kPoseLost),
            hal::kEncodersSilent | hal::kPoseLost);
  led.reset();
  EXPECT_EQ(line.value, 0);  // released dark
}

TEST(StatusIndicator, AMissingInputShowsAsDegraded) {
  drivers::testing::FakeOs os;
  drivers::testing::FakeGpio gpio(os);
  drivers::testing::RecordingDiagnostics diag;
  drivers::GpioLineConfig lc;
  lc.line = "1";
  drivers::StatusLed led(lc, gpio, diag);
  firmware::StatusIndicator indicator(led, true);
  indicator.show(hal::kHealthOk, 0);
  EXPECT_EQ(led.pattern(), LedPattern::kDegraded);
  EXPECT_EQ(indicator.next_due_ns(), 500 * kMs);
}

// Poses as published, with their health.
class PoseLog final : public hal::PoseSink {
 public:
  std::vector<hal::PoseEstimate> poses;
  void publish(const hal::PoseEstimate& p) override { poses.push_back(p); }
};

// The kidnapped scenario, lifted at 20 s for 3 s and set down `skip_s` of path further on.
struct KidnappedRun {
  std::string dir;
  std::vector<readers::GroundTruthPose> gt;
  bool ok = false;

  explicit KidnappedRun(double skip_s) {
    dir = (fs::temp_directory_path() /
           ("cleanslam_setdown_" + std::to_string(::getpid()) + "_" + std::to_string(skip_s)))
              .string();
    auto scenario = sim_hal::sim::load_scenario(
        "kidnapped", {"duration_s=45", "path.kidnap_at_s=20",
                      "path.kidnap_skip_s=" + std::to_string(skip_s), "path.lift_duration_s=3"});
    if (!scenario.ok() || !sim_hal::sim::simulate(*scenario, dir).ok()) {
      return;
    }
    auto g = readers::read_groundtruth_csv(dir + "/groundtruth.csv");
    if (!g.ok()) {
      return;
    }
    gt = g.value();
    ok = !gt.empty();
  }
  ~KidnappedRun() { fs::remove_all(dir); }

  [[nodiscard]] const readers::GroundTruthPose& at(hal::TimeNs t) const {
    std::size_t i = 0;
    while (i + 1 < gt.size() && gt[i + 1].t_ns <= t) {
      ++i;
    }
    return gt[i];
  }

  std::vector<hal::PoseEstimate> run(const std::string& policy) const {
    auto ds = readers::DatasetSource::open(dir);
    auto cfg = parse_config("", "", {"map_management.on_set_down=" + policy});
    if (!ds.ok() || !cfg.ok()) {
      ADD_FAILURE() << (ds.ok() ? joined(cfg.errors) : ds.error());
      return {};
    }
    cfg.config.calibration = ds->calibration();
    firmware::SlamEstimator est(cfg.config);
    firmware::Loop loop(cfg.config.loop, est);
    readers::DatasetSource source = std::move(ds.value());
    loop.add_source(&source);
    PoseLog log;
    loop.add_pose_sink(&log);
    firmware::VirtualClock clock;
    firmware::run_virtual(loop, clock, false, nullptr);
    return log.poses;
  }
};

double yaw_of(const std::array<double, 4>& q) {
  return std::atan2(2.0 * (q[0] * q[3] + q[1] * q[2]), 1.0 - 2.0 * (q[2] * q[2] + q[3] * q[3]));
}

// Planar distance to the ground truth expressed in the estimator's world frame: the body frame
// at the start (the first ground-truth pose).
double planar_error(const hal::PoseEstimate& p, const readers::GroundTruthPose& g,
                    const readers::GroundTruthPose& g0) {
  const double yaw0 = yaw_of(g0.orientation_wxyz);
  const double dx = g.position_m[0] - g0.position_m[0];
  const double dy = g.position_m[1] - g0.position_m[1];
  const double x = std::cos(yaw0) * dx + std::sin(yaw0) * dy;
  const double y = -std::sin(yaw0) * dx + std::cos(yaw0) * dy;
  return std::hypot(p.position_m[0] - x, p.position_m[1] - y);
}

// The first pose published after the set-down (the lift flag gone).
std::size_t first_after_set_down(const std::vector<hal::PoseEstimate>& poses) {
  bool lifted = false;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if ((poses[i].health & hal::kLifted) != 0) {
      lifted = true;
    } else if (lifted) {
      return i;
    }
  }
  return poses.size();
}

TEST(SetDown, NewMapStartsOverAtTheSetDownPoseRelocalizeKeepsTheMap) {
  const KidnappedRun sim(2.0);
  ASSERT_TRUE(sim.ok);
  const auto fresh = sim.run("new_map");
  const auto reloc = sim.run("relocalize");
  const std::size_t i_new = first_after_set_down(fresh);
  const std::size_t i_rel = first_after_set_down(reloc);
  ASSERT_LT(i_new, fresh.size());
  ASSERT_LT(i_rel, reloc.size());
  ASSERT_GT(fresh[i_new - 1].landmarks_in_map, 0);

  // new_map: the map is emptied, the world frame restarts at the set-down pose.
  EXPECT_EQ(fresh[i_new].landmarks_in_map, 0);
  EXPECT_LT(std::hypot(fresh[i_new].position_m[0], fresh[i_new].position_m[1]), 0.05);
  EXPECT_EQ(fresh[i_new].health & hal::kPoseLost, 0U);

  // relocalize: the map stays; the pose is lost until a visual update fuses, then found again
  // in the original world frame, near the ground truth.
  EXPECT_GT(reloc[i_rel].landmarks_in_map, 0);
  EXPECT_NE(reloc[i_rel].health & hal::kPoseLost, 0U);
  std::size_t found = i_rel;
  while (found < reloc.size() && (reloc[found].health & hal::kPoseLost) != 0) {
    ++found;
  }
  ASSERT_LT(found, reloc.size()) << "never relocalized";
  EXPECT_LT(reloc[found].t_ns - reloc[i_rel].t_ns, 5 * hal::kNsPerSecond);
  // The covariance carries the carry's uncertainty at the set-down.
  EXPECT_GT(reloc[i_rel].covariance[0], reloc[i_rel - 1].covariance[0] + 0.05);

  const hal::PoseEstimate& end_rel = reloc.back();
  const hal::PoseEstimate& end_new = fresh.back();
  const auto& g0 = sim.gt.front();
  const double err_rel = planar_error(end_rel, sim.at(end_rel.t_ns), g0);
  const double err_new = planar_error(end_new, sim.at(end_new.t_ns), g0);
  const double err_lift = planar_error(reloc[i_rel - 1], sim.at(reloc[i_rel - 1].t_ns), g0);
  std::printf("final planar error: relocalize %.3f m, new map %.3f m (at the set-down %.3f m)\n",
              err_rel, err_new, err_lift);
  EXPECT_LT(err_rel, 0.3);
  EXPECT_GT(err_new, 1.0);  // a new frame: far from the original world's ground truth
}

// The complete program on a robot whose devices are all missing: every one explained, the
// firmware keeps running (degraded) until SIGTERM and stops cleanly.
TEST(RobotProgram, MissingDevicesAreExplainedAndTheFirmwareRunsUntilStopped) {
  std::vector<std::string> args{"cleanslam",
                                "--set",
                                "source.kind=drivers",
                                "--set",
                                "source.can_interface=nocan7",
                                "--set",
                                "source.camera_device=/nonexistent/video9",
                                "--set",
                                "source.gpio_chip=/nonexistent/gpiochip9",
                                "--set",
                                "source.lift_line=3",
                                "--set",
                                "robot.status_led_line=1",
                                "--set",
                                "robot.gyro_ready_line=2",
                                "--set",
                                "sinks.can=true",
                                "--set",
                                "sinks.can_interface=nocan7"};
  std::vector<char*> argv;
  for (auto& a : args) {
    argv.push_back(a.data());
  }
  argv.push_back(nullptr);
  // SIGTERM after 1.5 s, again every 0.5 s until seen (it may come before the handler is in),
  // from a timer: process-directed like systemd's, no thread (qemu-user routes those poorly).
  sigevent ev{};
  ev.sigev_notify = SIGEV_SIGNAL;
  ev.sigev_signo = SIGTERM;
  timer_t timer{};
  ASSERT_EQ(::timer_create(CLOCK_MONOTONIC, &ev, &timer), 0);
  struct sigaction ignore {};
  struct sigaction old {};
  ignore.sa_handler = [](int) {};
  ::sigaction(SIGTERM, &ignore, &old);
  itimerspec when{};
  when.it_value.tv_nsec = 500'000'000;
  when.it_value.tv_sec = 1;
  when.it_interval.tv_nsec = 500'000'000;
  ::timer_settime(timer, 0, &when, nullptr);
  ::testing::internal::CaptureStderr();
  const int rc = firmware::program_main(static_cast<int>(args.size()), argv.data());
  const std::string err = ::testing::internal::GetCapturedStderr();
  ::timer_delete(timer);
  ::sigaction(SIGTERM, &old, nullptr);
  EXPECT_EQ(rc, 0) << err;
  for (const char* expected :
       {"'nocan7'", "cannot open camera '/nonexistent/video9'",
        "GPIO chip '/nonexistent/gpiochip9' for the lift switch not found",
        "for the status LED not found", "for the gyro data-ready input not found",
        "encoders silent", "stopped by signal, outputs flushed",
        "uncalibrated: calibration.camera.fx", "cleanslam-calibrate"}) {
    EXPECT_NE(err.find(expected), std::string::npos) << expected << "\n" << err;
  }
}

}  // namespace
}  // namespace cleanslam
