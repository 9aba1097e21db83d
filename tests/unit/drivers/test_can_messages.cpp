#include <cmath>
#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

#include "cleanslam/drivers/can_messages.hpp"

namespace cleanslam::drivers::can_map {
namespace {

Frame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  Frame f;
  f.id = id;
  f.length = static_cast<std::uint8_t>(bytes.size());
  std::copy(bytes.begin(), bytes.end(), f.data.begin());
  return f;
}

TEST(CanMessages, EncoderLayoutIsLittleEndianSigned24) {
  // left = 0x000102 = 258, right = -2 (0xFFFFFE), seq 7, status 0.
  EncoderMessage m;
  ASSERT_TRUE(decode(frame(kEncoderId, {0x02, 0x01, 0x00, 0xFE, 0xFF, 0xFF, 7, 0}), m));
  EXPECT_EQ(m.left_ticks24, 258);
  EXPECT_EQ(m.right_ticks24, -2);
  EXPECT_EQ(m.seq, 7);
}

TEST(CanMessages, GyroLayoutAndScale) {
  // rate = -1'500'000 µrad/s = 0xFFE91CA0, temperature 2537 = 25.37 °C, seq 200, saturated.
  GyroMessage m;
  ASSERT_TRUE(decode(frame(kGyroId, {0xA0, 0x1C, 0xE9, 0xFF, 0xE9, 0x09, 200, 1}), m));
  EXPECT_EQ(m.rate_raw, -1'500'000);
  EXPECT_NEAR(m.rate_rad_s(), -1.5, 1e-12);
  EXPECT_NEAR(m.temperature_c(), 25.37, 1e-9);
  EXPECT_EQ(m.seq, 200);
  EXPECT_EQ(m.status & kGyroSaturated, kGyroSaturated);
}

TEST(CanMessages, WrongLengthOrIdIsRejected) {
  EncoderMessage e;
  GyroMessage g;
  EXPECT_FALSE(decode(frame(kEncoderId, {1, 2, 3, 4, 5, 6, 7}), e));
  EXPECT_FALSE(decode(frame(kGyroId, {1, 2, 3, 4, 5, 6, 7, 8}), e));
  EXPECT_FALSE(decode(frame(kGyroId, {1, 2}), g));
}

TEST(CanMessages, EncodeDecodeRoundTrip) {
  EncoderMessage e{-8'388'608, 8'388'607, 255, 3};
  EncoderMessage e2;
  ASSERT_TRUE(decode(encode(e), e2));
  EXPECT_EQ(e2.left_ticks24, e.left_ticks24);
  EXPECT_EQ(e2.right_ticks24, e.right_ticks24);
  EXPECT_EQ(e2.seq, 255);
  GyroMessage g{std::numeric_limits<std::int32_t>::min(), -4000, 9, 0};
  GyroMessage g2;
  ASSERT_TRUE(decode(encode(g), g2));
  EXPECT_EQ(g2.rate_raw, g.rate_raw);
  EXPECT_EQ(g2.temperature_raw, -4000);
}

TEST(CanMessages, PoseFramesCarryPositionYawAndQuality) {
  hal::PoseEstimate p;
  p.position_m = {1.2345, -0.5, 0.0};
  const double yaw = 2.0;
  p.orientation_wxyz = {std::cos(yaw / 2), 0.0, 0.0, std::sin(yaw / 2)};
  p.covariance[0] = 0.01 * 0.01;
  p.covariance[7] = 0.02 * 0.02;
  p.covariance[35] = 0.05 * 0.05;
  p.health = hal::kCameraSilent | hal::kFewLandmarks;
  const PoseMessages m = encode_pose(p, 42);
  EXPECT_EQ(m.position.id, kPosePositionId);
  EXPECT_EQ(m.yaw_quality.id, kPoseYawId);
  // x = 12345 = 0x003039, y = -5000 = 0xFFEC78
  EXPECT_EQ(m.position.data[0], 0x39);
  EXPECT_EQ(m.position.data[1], 0x30);
  EXPECT_EQ(m.position.data[2], 0x00);
  EXPECT_EQ(m.position.data[3], 0x78);
  EXPECT_EQ(m.position.data[4], 0xEC);
  EXPECT_EQ(m.position.data[5], 0xFF);
  EXPECT_EQ(m.position.data[6], 42);
  // yaw 20000 = 0x4E20; sigma_xy = 0.02 m = 200; sigma_yaw = 0.05 rad = 500 = 0x01F4
  EXPECT_EQ(m.yaw_quality.data[0], 0x20);
  EXPECT_EQ(m.yaw_quality.data[1], 0x4E);
  EXPECT_EQ(m.yaw_quality.data[2], 200);
  EXPECT_EQ(m.yaw_quality.data[3], 0);
  EXPECT_EQ(m.yaw_quality.data[4], 0xF4);
  EXPECT_EQ(m.yaw_quality.data[5], 0x01);
  EXPECT_EQ(m.yaw_quality.data[6], 42);
  EXPECT_EQ(m.yaw_quality.data[7], hal::kCameraSilent | hal::kFewLandmarks);
}

TEST(CanMessages, PoseSaturatesOutOfRangeAndNonFinite) {
  hal::PoseEstimate p;
  p.position_m = {1e6, -std::numeric_limits<double>::infinity(), 0.0};
  p.covariance[0] = 1e9;
  p.covariance[35] = std::numeric_limits<double>::quiet_NaN();
  const PoseMessages m = encode_pose(p, 0);
  EXPECT_EQ(m.position.data[0], 0xFF);
  EXPECT_EQ(m.position.data[2], 0x7F);  // +8388607
  EXPECT_EQ(m.position.data[3], 0x01);
  EXPECT_EQ(m.position.data[5], 0x80);  // -8388607
  EXPECT_EQ(m.yaw_quality.data[2], 0xFF);
  EXPECT_EQ(m.yaw_quality.data[3], 0xFF);
  EXPECT_EQ(m.yaw_quality.data[4], 0xFF);  // NaN sigma reads as "unknown": maximum
  EXPECT_EQ(m.yaw_quality.data[5], 0xFF);
}

TEST(TickExtender, FollowsThe24BitWrap) {
  TickExtender t;
  EXPECT_EQ(t.extend(8'388'600), 8'388'600);
  EXPECT_EQ(t.extend(-8'388'600), 8'388'600 + 16);  // wrapped forward by 16 ticks
  EXPECT_EQ(t.extend(8'388'600), 8'388'600);        // and back
  TickExtender backwards;
  EXPECT_EQ(backwards.extend(-5), -5);
  EXPECT_EQ(backwards.extend(-20), -20);
}

TEST(TickExtender, ExtendedCountWrapsAt32Bits) {
  TickExtender t;
  std::int32_t v = 0;
  std::int32_t raw24 = 0;
  t.extend(0);
  // 600 steps of 4'000'000 ticks forward (each within the 24-bit half range).
  for (int i = 0; i < 600; ++i) {
    raw24 = static_cast<std::int32_t>((static_cast<std::uint32_t>(raw24) + 4'000'000U) & 0xFFFFFFU);
    if (raw24 >= (1 << 23)) {
      raw24 -= (1 << 24);
    }
    v = t.extend(raw24);
  }
  EXPECT_EQ(static_cast<std::uint32_t>(v), static_cast<std::uint32_t>(600ULL * 4'000'000ULL));
}

TEST(SequenceTracker, CountsGapsDuplicatesAndResets) {
  using R = SequenceTracker::Result;
  SequenceTracker s;
  EXPECT_EQ(s.observe(250), R::kFirst);
  EXPECT_EQ(s.observe(251), R::kInOrder);
  EXPECT_EQ(s.observe(2), R::kGap);  // 252..255, 0, 1 missing
  EXPECT_EQ(s.last_gap(), 6U);
  EXPECT_EQ(s.extended(), 250U + 8U);
  EXPECT_EQ(s.observe(2), R::kDuplicate);
  EXPECT_EQ(s.observe(1), R::kOutOfOrder);
  EXPECT_EQ(s.extended(), 259U);
  EXPECT_EQ(s.observe(2), R::kInOrder);
  EXPECT_EQ(s.extended(), 260U);
  s.reset();
  EXPECT_EQ(s.observe(77), R::kFirst);
  EXPECT_EQ(s.extended(), 261U);
}

TEST(Yaw, OfQuaternion) {
  for (double yaw : {-3.0, -1.0, 0.0, 0.5, 3.1}) {
    EXPECT_NEAR(yaw_of({std::cos(yaw / 2), 0, 0, std::sin(yaw / 2)}), yaw, 1e-12);
  }
}

}  // namespace
}  // namespace cleanslam::drivers::can_map
