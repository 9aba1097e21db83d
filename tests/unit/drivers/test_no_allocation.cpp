#include <gtest/gtest.h>

#include "allocation_counter.hpp"
#include "cleanslam/drivers/can_base_board.hpp"
#include "cleanslam/drivers/can_messages.hpp"
#include "cleanslam/drivers/can_pose_sink.hpp"
#include "cleanslam/drivers/lift_switch.hpp"
#include "cleanslam/drivers/v4l2_camera.hpp"
#include "fake_gpio.hpp"
#include "fake_os.hpp"
#include "fake_v4l2.hpp"

// The drivers' steady-state paths run at 100 Hz inside the loop: they allocate nothing.
namespace cleanslam::drivers {
namespace {

using testing::FakeGpio;
using testing::FakeOs;
using testing::FakeV4l2;
using testing::RecordingDiagnostics;

TEST(NoAllocation, CanReadAndPublish) {
  FakeOs os;
  RecordingDiagnostics diag;
  CanBaseBoardConfig config;
  config.interface = "vcan0";
  CanBaseBoard board(config, os, diag);
  CanPoseSink sink("vcan0", os, diag);
  os.sent.reserve(64);
  for (std::uint8_t i = 0; i < 20; ++i) {
    const auto f = can_map::encode(can_map::GyroMessage{1000 * i, 0, i, 0});
    os.receive(f.id, {f.data[0], f.data[1], f.data[2], f.data[3], f.data[4], f.data[5], f.data[6],
                      f.data[7]});
  }
  hal::SensorEvent e;
  int events = 0;
  hal::PoseEstimate pose;
  test::AllocationScope scope;
  while (board.read(e)) {
    ++events;
  }
  sink.publish(pose);
  EXPECT_EQ(scope.count(), 0U);
  EXPECT_EQ(events, 20);
  EXPECT_TRUE(diag.entries.empty()) << diag.all();
}

TEST(NoAllocation, CameraRead) {
  FakeV4l2 os;
  RecordingDiagnostics diag;
  V4l2CameraConfig config;
  config.rate_hz = 2.0;
  V4l2Camera camera(config, os, diag);
  const std::size_t reports = diag.entries.size();
  hal::SensorEvent e;
  int frames = 0;
  for (int i = 0; i < 10; ++i) {
    os.mono_ns += 100 * hal::kNsPerMillisecond;
    os.produce(os.mono_ns, [](int x, int y) { return x + y; });
    test::AllocationScope scope;
    frames += camera.read(e) ? 1 : 0;
    EXPECT_EQ(scope.count(), 0U);
  }
  EXPECT_EQ(frames, 2);
  EXPECT_EQ(diag.entries.size(), reports) << diag.all();
}

TEST(NoAllocation, LiftRead) {
  FakeOs os;
  FakeGpio gpio(os);
  RecordingDiagnostics diag;
  LiftSwitchConfig config;
  config.gpio.line = "3";
  LiftSwitch lift(config, gpio, os, diag);
  gpio.edge("gpiochip0", 3, true, os.mono_ns);
  hal::SensorEvent e;
  test::AllocationScope scope;
  EXPECT_TRUE(lift.read(e));
  EXPECT_EQ(scope.count(), 0U);
}

}  // namespace
}  // namespace cleanslam::drivers
