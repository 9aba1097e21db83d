#include <gtest/gtest.h>

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

}  // namespace
}  // namespace cleanslam::drivers
