#include <gtest/gtest.h>

#include "cleanslam/drivers/can_messages.hpp"
#include "cleanslam/drivers/can_pose_sink.hpp"
#include "fake_os.hpp"

namespace cleanslam::drivers {
namespace {

using testing::FakeOs;
using testing::RecordingDiagnostics;

TEST(CanPoseSink, SendsPositionThenYawFramesWithOneSequence) {
  FakeOs os;
  RecordingDiagnostics diag;
  CanPoseSink sink("vcan0", os, diag);
  hal::PoseEstimate p;
  p.position_m = {0.5, 0.25, 0.0};
  sink.publish(p);
  sink.publish(p);
  ASSERT_EQ(os.sent.size(), 4U);
  EXPECT_EQ(os.sent[0].can_id, can_map::kPosePositionId);
  EXPECT_EQ(os.sent[1].can_id, can_map::kPoseYawId);
  EXPECT_EQ(os.sent[0].len, 8);
  EXPECT_EQ(os.sent[0].data[0] | (os.sent[0].data[1] << 8), 5000);
  EXPECT_EQ(os.sent[0].data[6], 0);
  EXPECT_EQ(os.sent[1].data[6], 0);
  EXPECT_EQ(os.sent[2].data[6], 1);
  EXPECT_EQ(sink.stats().frames_sent, 4U);
}

TEST(CanPoseSink, FullTransmitQueueDropsAndCounts) {
  FakeOs os;
  RecordingDiagnostics diag;
  CanPoseSink sink("vcan0", os, diag);
  os.write_error = ENOBUFS;
  sink.publish(hal::PoseEstimate{});
  EXPECT_EQ(sink.stats().frames_dropped, 2U);
  EXPECT_TRUE(sink.connected());
  EXPECT_TRUE(diag.any_contains("No buffer space")) << diag.all();
}

TEST(CanPoseSink, MissingInterfaceIsExplainedAndRetried) {
  FakeOs os;
  os.interfaces.clear();
  RecordingDiagnostics diag;
  CanPoseSink sink("can7", os, diag);
  EXPECT_FALSE(sink.connected());
  EXPECT_TRUE(diag.any_contains("cannot open interface 'can7'")) << diag.all();
  sink.publish(hal::PoseEstimate{});
  EXPECT_TRUE(os.sent.empty());
  os.interfaces["can7"] = 9;
  os.mono_ns += hal::kNsPerSecond;
  sink.publish(hal::PoseEstimate{});
  EXPECT_TRUE(sink.connected());
  EXPECT_EQ(os.sent.size(), 2U);
}

}  // namespace
}  // namespace cleanslam::drivers
