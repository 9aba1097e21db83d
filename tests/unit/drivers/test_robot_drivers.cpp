#include <gtest/gtest.h>

#include "cleanslam/drivers/can_messages.hpp"
#include "cleanslam/drivers/robot_drivers.hpp"
#include "fake_gpio.hpp"
#include "fake_v4l2.hpp"

namespace cleanslam::drivers {
namespace {

using testing::FakeGpio;
using testing::FakeV4l2;
using testing::RecordingDiagnostics;

TEST(RobotDrivers, BuildsTheConfiguredPartsOnly) {
  FakeV4l2 os;
  FakeGpio gpio(os);
  RecordingDiagnostics diag;
  RobotDriversConfig c;
  c.can.interface = "vcan0";
  c.lift.gpio.line = "3";
  c.status_led.line = "1";
  c.pose_interface = "vcan0";
  c.camera.device = "";
  RobotDrivers d(c, os, gpio, diag);
  EXPECT_EQ(d.source_count(), 2);
  EXPECT_EQ(d.sources()[0], d.base_board());
  EXPECT_EQ(d.sources()[1], d.lift());
  EXPECT_EQ(d.camera(), nullptr);
  ASSERT_NE(d.pose_sink(), nullptr);
  ASSERT_NE(d.status_led(), nullptr);
  EXPECT_TRUE(d.status_led()->available());
  EXPECT_TRUE(diag.entries.empty()) << diag.all();
}

TEST(RobotDrivers, MissingDevicesLeaveSourcesThatStayQuiet) {
  FakeV4l2 os;
  os.present = false;
  os.interfaces.clear();
  FakeGpio gpio(os);
  RecordingDiagnostics diag;
  RobotDriversConfig c;
  c.can.interface = "can0";
  c.camera.device = "/dev/video0";
  c.lift.gpio.chip = "gpiochip4";
  c.lift.gpio.line = "LIFT";
  RobotDrivers d(c, os, gpio, diag);
  ASSERT_EQ(d.source_count(), 3);
  hal::SensorEvent e;
  for (int i = 0; i < d.source_count(); ++i) {
    EXPECT_GE(d.sources()[i]->fd(), 0);
    EXPECT_FALSE(d.sources()[i]->read(e));
  }
  EXPECT_TRUE(diag.any_contains("interface 'can0' not found")) << diag.all();
  EXPECT_TRUE(diag.any_contains("cannot open camera '/dev/video0'")) << diag.all();
  EXPECT_TRUE(diag.any_contains("GPIO chip 'gpiochip4' for the lift switch not found"))
      << diag.all();
}

void receive_gyro(FakeV4l2& os, std::uint8_t seq, hal::TimeNs age_ns) {
  const auto f = can_map::encode(can_map::GyroMessage{100'000, 2500, seq, 0});
  os.receive(
      f.id,
      {f.data[0], f.data[1], f.data[2], f.data[3], f.data[4], f.data[5], f.data[6], f.data[7]},
      age_ns);
}

hal::TimeNs next_gyro_time(RobotDrivers& d) {
  hal::SensorEvent e;
  while (d.base_board()->read(e)) {
    if (e.kind == hal::SensorEvent::Kind::kGyro) {
      return e.gyro.t_ns;
    }
  }
  return -1;
}

// The base board's gyro frames take the data-ready edge's kernel time; without an edge, the CAN
// reception time (an outage reported once, its end too).
TEST(RobotDrivers, GyroFramesTakeTheDataReadyEdgeTimeElseTheCanTime) {
  FakeV4l2 os;
  FakeGpio gpio(os);
  RecordingDiagnostics diag;
  RobotDriversConfig c;
  c.can.interface = "vcan0";
  c.camera.device = "";
  c.gyro_ready.gpio.line = "2";
  RobotDrivers d(c, os, gpio, diag);
  ASSERT_NE(d.gyro_ready(), nullptr);
  ASSERT_TRUE(d.gyro_ready()->available()) << diag.all();
  EXPECT_FALSE(d.inputs_missing());
  using testing::kMs;
  const hal::TimeNs t0 = os.mono_ns;
  gpio.edge("gpiochip0", 2, true, t0 - 3 * kMs);
  receive_gyro(os, 0, 1 * kMs);  // received 2 ms after the edge
  EXPECT_EQ(next_gyro_time(d), t0 - 3 * kMs);
  receive_gyro(os, 1, 0);  // no edge: CAN time
  EXPECT_EQ(next_gyro_time(d), t0);
  EXPECT_TRUE(diag.any_contains("no data-ready edge within 8.0 ms")) << diag.all();
  const auto messages = diag.entries.size();
  receive_gyro(os, 2, 0);
  EXPECT_EQ(next_gyro_time(d), t0);
  EXPECT_EQ(diag.entries.size(), messages);  // once per outage
  os.mono_ns += 10 * kMs;
  gpio.edge("gpiochip0", 2, true, os.mono_ns - kMs);
  receive_gyro(os, 3, 0);
  EXPECT_EQ(next_gyro_time(d), os.mono_ns - kMs);
  EXPECT_TRUE(diag.any_contains("data-ready edges are back")) << diag.all();
  EXPECT_EQ(d.gyro_ready()->stats().matched, 2U);
  EXPECT_EQ(d.gyro_ready()->stats().unmatched, 2U);
}

// A data-ready chip or line that does not exist: explained, and the base board runs on CAN time.
TEST(RobotDrivers, MissingDataReadyLineLeavesCanTimeAndIsExplained) {
  for (const char* chip : {"gpiochip7", "gpiochip0"}) {
    FakeV4l2 os;
    FakeGpio gpio(os);
    RecordingDiagnostics diag;
    RobotDriversConfig c;
    c.can.interface = "vcan0";
    c.camera.device = "";
    c.gyro_ready.gpio.chip = chip;
    c.gyro_ready.gpio.line = "DRDY";
    RobotDrivers d(c, os, gpio, diag);
    EXPECT_TRUE(d.inputs_missing());
    EXPECT_TRUE(diag.any_contains("gyro data-ready input")) << diag.all();
    EXPECT_TRUE(diag.any_contains(std::string(chip) == "gpiochip7" ? "gpiochip7" : "DRDY"))
        << diag.all();
    receive_gyro(os, 0, 2 * hal::kNsPerMillisecond);
    EXPECT_EQ(next_gyro_time(d), os.mono_ns - 2 * hal::kNsPerMillisecond);
  }
}

}  // namespace
}  // namespace cleanslam::drivers
