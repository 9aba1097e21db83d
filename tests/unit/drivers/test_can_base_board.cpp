#include <linux/can.h>
#include <linux/can/error.h>

#include <gtest/gtest.h>

#include "cleanslam/drivers/can_base_board.hpp"
#include "cleanslam/drivers/can_messages.hpp"
#include "fake_os.hpp"

namespace cleanslam::drivers {
namespace {

using testing::FakeOs;
using testing::RecordingDiagnostics;
using Kind = hal::SensorEvent::Kind;

class CanBaseBoardTest : public ::testing::Test {
 protected:
  FakeOs os;
  RecordingDiagnostics diag;
  CanBaseBoardConfig config() {
    CanBaseBoardConfig c;
    c.interface = "vcan0";
    return c;
  }
  void encoder(std::int32_t left, std::int32_t right, std::uint8_t seq, hal::TimeNs age = 0) {
    const auto f = can_map::encode(can_map::EncoderMessage{left, right, seq, 0});
    os.receive(
        f.id,
        {f.data[0], f.data[1], f.data[2], f.data[3], f.data[4], f.data[5], f.data[6], f.data[7]},
        age);
  }
  void gyro(std::int32_t rate_urad, std::uint8_t seq, hal::TimeNs age = 0) {
    const auto f = can_map::encode(can_map::GyroMessage{rate_urad, 2500, seq, 0});
    os.receive(
        f.id,
        {f.data[0], f.data[1], f.data[2], f.data[3], f.data[4], f.data[5], f.data[6], f.data[7]},
        age);
  }
};

TEST_F(CanBaseBoardTest, InstallsKernelFiltersTimeStampsAndBinds) {
  CanBaseBoard board(config(), os, diag);
  EXPECT_TRUE(board.connected());
  ASSERT_EQ(os.filters.size(), 2U);
  EXPECT_EQ(os.filters[0].can_id, can_map::kEncoderId);
  EXPECT_EQ(os.filters[1].can_id, can_map::kGyroId);
  EXPECT_EQ(os.filters[0].can_mask & CAN_SFF_MASK, CAN_SFF_MASK);
  EXPECT_NE(os.filters[0].can_mask & CAN_EFF_FLAG, 0U);
  EXPECT_EQ(os.error_mask & CAN_ERR_BUSOFF, CAN_ERR_BUSOFF);
  EXPECT_TRUE(os.timestamps_enabled);
  EXPECT_EQ(os.bound_ifindex, 3);
  EXPECT_GE(board.fd(), 0);
  EXPECT_TRUE(diag.entries.empty()) << diag.all();
}

TEST_F(CanBaseBoardTest, DecodesFramesWithKernelTimeOnTheMonotonicClock) {
  CanBaseBoard board(config(), os, diag);
  encoder(1000, -2000, 5, 3 * hal::kNsPerMillisecond);
  gyro(250'000, 17, 1 * hal::kNsPerMillisecond);
  hal::SensorEvent e;
  ASSERT_TRUE(board.read(e));
  EXPECT_EQ(e.kind, Kind::kEncoder);
  EXPECT_EQ(e.encoder.left_ticks, 1000);
  EXPECT_EQ(e.encoder.right_ticks, -2000);
  EXPECT_EQ(e.encoder.t_ns, os.mono_ns - 3 * hal::kNsPerMillisecond);
  ASSERT_TRUE(board.read(e));
  EXPECT_EQ(e.kind, Kind::kGyro);
  EXPECT_NEAR(e.gyro.wz_rad_s, 0.25, 1e-12);
  EXPECT_EQ(e.gyro.t_ns, os.mono_ns - 1 * hal::kNsPerMillisecond);
  EXPECT_FALSE(board.read(e));
  EXPECT_EQ(board.stats().encoder_frames, 1U);
  EXPECT_EQ(board.stats().gyro_frames, 1U);
  EXPECT_NEAR(board.stats().gyro_temperature_c, 25.0, 1e-9);
}

TEST_F(CanBaseBoardTest, WithoutKernelStampUsesReceiveTime) {
  CanBaseBoard board(config(), os, diag);
  gyro(1, 1);
  os.inbox.back().realtime_ns = -1;
  hal::SensorEvent e;
  ASSERT_TRUE(board.read(e));
  EXPECT_EQ(e.gyro.t_ns, os.mono_ns);
}

TEST_F(CanBaseBoardTest, WrongLengthIsDroppedCountedAndExplained) {
  CanBaseBoard board(config(), os, diag);
  os.receive(can_map::kGyroId, {1, 2, 3, 4, 5});
  gyro(100, 1);
  hal::SensorEvent e;
  ASSERT_TRUE(board.read(e));
  EXPECT_EQ(e.kind, Kind::kGyro);
  EXPECT_EQ(board.stats().wrong_length, 1U);
  EXPECT_TRUE(diag.any_contains("frame 0x102 has 5 data bytes, expected 8")) << diag.all();
}

TEST_F(CanBaseBoardTest, UnknownIdIsDroppedCountedAndExplained) {
  CanBaseBoard board(config(), os, diag);
  os.receive(0x321, {1, 2, 3, 4, 5, 6, 7, 8});
  hal::SensorEvent e;
  EXPECT_FALSE(board.read(e));
  EXPECT_EQ(board.stats().unknown_id, 1U);
  EXPECT_TRUE(diag.any_contains("unknown id 0x321")) << diag.all();
}

TEST_F(CanBaseBoardTest, SequenceGapsCountDroppedFramesAndDuplicatesAreDropped) {
  CanBaseBoard board(config(), os, diag);
  hal::SensorEvent e;
  gyro(1, 10);
  gyro(2, 11);
  gyro(3, 14);  // 12, 13 lost
  gyro(4, 14);  // duplicate
  gyro(5, 15);
  int events = 0;
  std::vector<std::uint32_t> seqs;
  while (board.read(e)) {
    ++events;
    seqs.push_back(e.gyro.seq);
  }
  EXPECT_EQ(events, 4);
  EXPECT_EQ(seqs, (std::vector<std::uint32_t>{10, 11, 14, 15}));
  EXPECT_EQ(board.stats().gyro_dropped, 2U);
  EXPECT_EQ(board.stats().duplicates, 1U);
  EXPECT_TRUE(diag.any_contains("2 gyro frame(s) missing before sequence 14")) << diag.all();
}

TEST_F(CanBaseBoardTest, EncoderTicksAreExtendedAcrossThe24BitWrap) {
  CanBaseBoard board(config(), os, diag);
  hal::SensorEvent e;
  encoder(8'388'000, 0, 0);
  encoder(-8'388'000, 0, 1);  // +1216 ticks across the wrap
  ASSERT_TRUE(board.read(e));
  ASSERT_TRUE(board.read(e));
  EXPECT_EQ(e.encoder.left_ticks, 8'388'000 + 1216);
  EXPECT_EQ(hal::tick_delta(e.encoder.left_ticks, 8'388'000), 1216);
}

TEST_F(CanBaseBoardTest, BusOffIsReportedAndRecoveryNoticed) {
  CanBaseBoard board(config(), os, diag);
  hal::SensorEvent e;
  os.receive(CAN_ERR_FLAG | CAN_ERR_BUSOFF, {0, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_FALSE(board.read(e));
  EXPECT_TRUE(board.bus_off());
  EXPECT_EQ(board.stats().bus_off, 1U);
  EXPECT_TRUE(diag.any_contains("is bus-off")) << diag.all();
  os.receive(CAN_ERR_FLAG | CAN_ERR_RESTARTED, {0, 0, 0, 0, 0, 0, 0, 0});
  gyro(7, 200);
  ASSERT_TRUE(board.read(e));
  EXPECT_FALSE(board.bus_off());
  EXPECT_EQ(board.stats().bus_off_recovered, 1U);
  EXPECT_TRUE(diag.any_contains("recovered from bus-off")) << diag.all();
}

TEST_F(CanBaseBoardTest, ControllerErrorFramesAreCountedAndDescribed) {
  CanBaseBoard board(config(), os, diag);
  hal::SensorEvent e;
  os.receive(CAN_ERR_FLAG | CAN_ERR_CRTL, {0, CAN_ERR_CRTL_RX_OVERFLOW, 0, 0, 0, 0, 0, 0});
  EXPECT_FALSE(board.read(e));
  EXPECT_EQ(board.stats().controller_errors, 1U);
  EXPECT_EQ(board.stats().error_frames, 1U);
  EXPECT_TRUE(diag.any_contains("controller 0x01")) << diag.all();
}

TEST_F(CanBaseBoardTest, MissingInterfaceDegradesThenReopensAfterBackoff) {
  os.interfaces.clear();
  CanBaseBoard board(config(), os, diag);
  EXPECT_FALSE(board.connected());
  EXPECT_GE(board.fd(), 0);  // the loop can still poll it: the back-off timer
  EXPECT_TRUE(diag.any_contains("interface 'vcan0' not found")) << diag.all();
  EXPECT_EQ(os.timer_delay_ns, 100 * hal::kNsPerMillisecond);
  hal::SensorEvent e;
  os.mono_ns += 50 * hal::kNsPerMillisecond;
  EXPECT_FALSE(board.read(e));
  EXPECT_FALSE(board.connected());
  os.mono_ns += 60 * hal::kNsPerMillisecond;
  EXPECT_FALSE(board.read(e));  // retried, still missing: longer back-off
  EXPECT_EQ(os.timer_delay_ns, 200 * hal::kNsPerMillisecond);
  os.interfaces["vcan0"] = 4;
  os.mono_ns += 200 * hal::kNsPerMillisecond;
  gyro(1, 1);
  EXPECT_TRUE(board.read(e));
  EXPECT_TRUE(board.connected());
  EXPECT_EQ(os.bound_ifindex, 4);
}

TEST_F(CanBaseBoardTest, VanishedInterfaceIsReopened) {
  CanBaseBoard board(config(), os, diag);
  hal::SensorEvent e;
  os.receive_error(ENODEV);
  EXPECT_FALSE(board.read(e));
  EXPECT_FALSE(board.connected());
  EXPECT_TRUE(diag.any_contains("failed (No such device)")) << diag.all();
  EXPECT_EQ(os.open_fds.size(), 2U);  // epoll and timer only: the socket was closed
  os.mono_ns += hal::kNsPerSecond;
  gyro(1, 1);
  EXPECT_TRUE(board.read(e));
  EXPECT_EQ(os.sockets_opened, 2);
}

TEST_F(CanBaseBoardTest, OneReadIsBounded) {
  auto c = config();
  c.max_frames_per_read = 4;
  CanBaseBoard board(c, os, diag);
  for (int i = 0; i < 10; ++i) {
    os.receive(0x321, {1, 2, 3, 4, 5, 6, 7, 8});
  }
  hal::SensorEvent e;
  EXPECT_FALSE(board.read(e));
  EXPECT_EQ(os.inbox.size(), 6U);
}

}  // namespace
}  // namespace cleanslam::drivers
