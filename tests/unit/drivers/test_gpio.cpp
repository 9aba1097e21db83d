#include <gtest/gtest.h>

#include "cleanslam/drivers/gyro_data_ready.hpp"
#include "cleanslam/drivers/lift_switch.hpp"
#include "cleanslam/drivers/status_led.hpp"
#include "fake_gpio.hpp"
#include "fake_os.hpp"

namespace cleanslam::drivers {
namespace {

using testing::FakeGpio;
using testing::FakeOs;
using testing::kMs;
using testing::RecordingDiagnostics;

class GpioTest : public ::testing::Test {
 protected:
  FakeOs os;
  FakeGpio gpio{os};
  RecordingDiagnostics diag;
  static LiftSwitchConfig lift_config(const char* chip = "gpiochip0", const char* line = "3") {
    LiftSwitchConfig c;
    c.gpio.chip = chip;
    c.gpio.line = line;
    return c;
  }
};

TEST_F(GpioTest, LiftAndSetDownArriveAsLiftEvents) {
  LiftSwitch lift(lift_config(), gpio, os, diag);
  ASSERT_TRUE(lift.available()) << diag.all();
  EXPECT_TRUE(gpio.line("gpiochip0", 3).requested);
  hal::SensorEvent e;
  EXPECT_FALSE(lift.read(e));
  gpio.edge("gpiochip0", 3, true, os.mono_ns);
  ASSERT_TRUE(lift.read(e));
  EXPECT_EQ(e.kind, hal::SensorEvent::Kind::kLift);
  EXPECT_TRUE(e.lifted);
  os.mono_ns += 500 * kMs;
  EXPECT_FALSE(lift.read(e));  // debounce timer over, level still high: no new event
  gpio.edge("gpiochip0", 3, false, os.mono_ns);
  ASSERT_TRUE(lift.read(e));
  EXPECT_FALSE(e.lifted);
  EXPECT_EQ(lift.stats().lifts, 1U);
  EXPECT_EQ(lift.stats().set_downs, 1U);
}

TEST_F(GpioTest, BounceIsIgnoredAndTheLevelDecidesAfterTheWindow) {
  LiftSwitch lift(lift_config(), gpio, os, diag);
  hal::SensorEvent e;
  gpio.edge("gpiochip0", 3, true, os.mono_ns);
  ASSERT_TRUE(lift.read(e));
  EXPECT_TRUE(e.lifted);
  gpio.edge("gpiochip0", 3, false, os.mono_ns + 1 * kMs);
  gpio.edge("gpiochip0", 3, true, os.mono_ns + 2 * kMs);
  gpio.edge("gpiochip0", 3, false, os.mono_ns + 3 * kMs);  // it really was set down
  os.mono_ns += 5 * kMs;
  EXPECT_FALSE(lift.read(e));
  EXPECT_EQ(lift.stats().bounces, 3U);
  os.mono_ns += 20 * kMs;
  ASSERT_TRUE(lift.read(e));
  EXPECT_FALSE(e.lifted);
}

TEST_F(GpioTest, StartingLiftedIsReportedOnce) {
  gpio.line("gpiochip0", 3).value = 1;
  LiftSwitch lift(lift_config(), gpio, os, diag);
  hal::SensorEvent e;
  ASSERT_TRUE(lift.read(e));
  EXPECT_TRUE(e.lifted);
  EXPECT_FALSE(lift.read(e));
}

TEST_F(GpioTest, ActiveLowSwitchAndLineByName) {
  auto c = lift_config("gpiochip0", "LIFT");
  c.gpio.active_low = true;
  gpio.line("gpiochip0", 5).value = 1;  // released: high
  LiftSwitch lift(c, gpio, os, diag);
  ASSERT_TRUE(lift.available()) << diag.all();
  hal::SensorEvent e;
  EXPECT_FALSE(lift.read(e));
  gpio.edge("gpiochip0", 5, false, os.mono_ns);  // pulled low: lifted
  ASSERT_TRUE(lift.read(e));
  EXPECT_TRUE(e.lifted);
}

TEST_F(GpioTest, MissingChipIsExplainedAndTheSourceStaysQuiet) {
  LiftSwitch lift(lift_config("gpiochip9", "3"), gpio, os, diag);
  EXPECT_FALSE(lift.available());
  EXPECT_GE(lift.fd(), 0);
  hal::SensorEvent e;
  EXPECT_FALSE(lift.read(e));
  EXPECT_TRUE(diag.any_contains("GPIO chip 'gpiochip9' for the lift switch not found"))
      << diag.all();
  EXPECT_TRUE(diag.any_contains("chips present: gpiochip0 [pl061, 8 lines]")) << diag.all();
}

TEST_F(GpioTest, MissingLineIsExplained) {
  LiftSwitch by_name(lift_config("gpiochip0", "NO_SUCH"), gpio, os, diag);
  LiftSwitch by_offset(lift_config("gpiochip0", "42"), gpio, os, diag);
  EXPECT_FALSE(by_name.available());
  EXPECT_FALSE(by_offset.available());
  EXPECT_TRUE(
      diag.any_contains("GPIO line 'NO_SUCH' for the lift switch not found on chip "
                        "'gpiochip0' (8 lines)"))
      << diag.all();
  EXPECT_TRUE(diag.any_contains("GPIO line '42'")) << diag.all();
  EXPECT_EQ(gpio.open_chips, 0);
}

TEST_F(GpioTest, BusyLineIsExplained) {
  gpio.line("gpiochip0", 3).busy = true;
  LiftSwitch lift(lift_config(), gpio, os, diag);
  EXPECT_FALSE(lift.available());
  EXPECT_TRUE(diag.any_contains("Device or resource busy")) << diag.all();
}

TEST(LedPattern, Levels) {
  EXPECT_EQ(led_level(LedPattern::kOk, 0), 1);
  EXPECT_EQ(led_level(LedPattern::kOk, 12345 * kMs), 1);
  EXPECT_EQ(led_next_change(LedPattern::kOk, 0), -1);
  EXPECT_EQ(led_level(LedPattern::kOff, 0), 0);
  EXPECT_EQ(led_level(LedPattern::kDegraded, 0), 1);
  EXPECT_EQ(led_level(LedPattern::kDegraded, 499 * kMs), 1);
  EXPECT_EQ(led_level(LedPattern::kDegraded, 500 * kMs), 0);
  EXPECT_EQ(led_level(LedPattern::kDegraded, 1000 * kMs), 1);
  EXPECT_EQ(led_next_change(LedPattern::kDegraded, 10 * kMs), 500 * kMs);
  EXPECT_EQ(led_level(LedPattern::kFault, 130 * kMs), 0);
  EXPECT_EQ(led_next_change(LedPattern::kFault, 130 * kMs), 250 * kMs);
}

TEST_F(GpioTest, StatusLedDrivesItsLine) {
  GpioLineConfig c;
  c.line = "1";
  StatusLed led(c, gpio, diag);
  ASSERT_TRUE(led.available()) << diag.all();
  auto& line = gpio.line("gpiochip0", 1);
  EXPECT_TRUE(line.output);
  led.set_pattern(LedPattern::kOk, 0);
  EXPECT_EQ(line.value, 1);
  EXPECT_EQ(led.next_change_ns(), -1);
  led.set_pattern(LedPattern::kFault, 1000 * kMs);
  EXPECT_EQ(line.value, 1);
  EXPECT_EQ(led.next_change_ns(), 1125 * kMs);
  led.update(1125 * kMs);
  EXPECT_EQ(line.value, 0);
  led.update(1250 * kMs);
  EXPECT_EQ(line.value, 1);
  const auto writes = line.writes.size();
  led.update(1260 * kMs);
  EXPECT_EQ(line.writes.size(), writes);  // no redundant writes
}

TEST_F(GpioTest, StatusLedWithoutLineStillTracksThePattern) {
  GpioLineConfig c;
  c.chip = "nope";
  c.line = "1";
  StatusLed led(c, gpio, diag);
  EXPECT_FALSE(led.available());
  led.set_pattern(LedPattern::kDegraded, 0);
  EXPECT_EQ(led.level(), 1);
  EXPECT_TRUE(diag.any_contains("status LED")) << diag.all();
}

TEST_F(GpioTest, DataReadyEdgesTimeStampGyroFrames) {
  GyroDataReadyConfig c;
  c.gpio.line = "2";
  GyroDataReady drdy(c, gpio, os, diag);
  ASSERT_TRUE(drdy.available());
  const hal::TimeNs t0 = os.mono_ns;
  gpio.edge("gpiochip0", 2, true, t0);
  gpio.edge("gpiochip0", 2, false, t0 + kMs);
  gpio.edge("gpiochip0", 2, true, t0 + 10 * kMs);
  hal::TimeNs t = 0;
  ASSERT_TRUE(drdy.sample_time(t0 + 3 * kMs, t));
  EXPECT_EQ(t, t0);
  ASSERT_TRUE(drdy.sample_time(t0 + 12 * kMs, t));
  EXPECT_EQ(t, t0 + 10 * kMs);
  // No edge for this frame: the reception time stays.
  EXPECT_FALSE(drdy.sample_time(t0 + 22 * kMs, t));
  // A stale edge is skipped.
  gpio.edge("gpiochip0", 2, true, t0 + 25 * kMs);
  EXPECT_FALSE(drdy.sample_time(t0 + 40 * kMs, t));
  EXPECT_EQ(drdy.stats().matched, 2U);
  EXPECT_EQ(drdy.stats().unmatched, 2U);
}

}  // namespace
}  // namespace cleanslam::drivers
