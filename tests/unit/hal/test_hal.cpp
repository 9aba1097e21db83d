#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/frame.hpp"
#include "cleanslam/hal/samples.hpp"
#include "cleanslam/hal/time.hpp"

namespace cleanslam::hal {
namespace {

TEST(TickDelta, PlainDifference) {
  EXPECT_EQ(tick_delta(1200, 1000), 200);
  EXPECT_EQ(tick_delta(1000, 1200), -200);
}

TEST(TickDelta, AcrossPositiveWrapAround) {
  const std::int32_t before = std::numeric_limits<std::int32_t>::max() - 5;
  const std::int32_t after = std::numeric_limits<std::int32_t>::min() + 4;
  EXPECT_EQ(tick_delta(after, before), 10);
  EXPECT_EQ(tick_delta(before, after), -10);
}

TEST(Time, SaturatingArithmeticAtEveryBoundary) {
  constexpr TimeNs kYear = TimeNs{365} * 86'400 * kNsPerSecond;
  constexpr TimeNs kNineE18 = 9'000'000'000'000'000'000;
  EXPECT_EQ(add_saturated(kTimeMax, 1), kTimeMax);
  EXPECT_EQ(add_saturated(kTimeMax, kTimeMax), kTimeMax);
  EXPECT_EQ(add_saturated(kNineE18, kNineE18), kTimeMax);
  EXPECT_EQ(add_saturated(kNineE18, kYear), kNineE18 + kYear);  // still fits
  EXPECT_EQ(add_saturated(kTimeMax - kYear, kYear), kTimeMax);
  EXPECT_EQ(add_saturated(kTimeMin, -1), kTimeMin);
  EXPECT_EQ(add_saturated(kTimeMin, kTimeMax), -1);
  EXPECT_EQ(sub_saturated(kTimeMin, 1), kTimeMin);
  EXPECT_EQ(sub_saturated(kTimeMax, kTimeMin), kTimeMax);
  EXPECT_EQ(sub_saturated(kTimeMin, kTimeMax), kTimeMin);
  EXPECT_EQ(sub_saturated(0, kTimeMin), kTimeMax);
  EXPECT_EQ(sub_saturated(-kNineE18, kNineE18), kTimeMin);
  EXPECT_EQ(sub_saturated(kYear, 2 * kYear), -kYear);
  EXPECT_EQ(add_saturated(1, 2), 3);
  EXPECT_EQ(sub_saturated(1, 2), -1);
}

TEST(Time, SecondsRoundTrip) {
  EXPECT_EQ(from_seconds(1.5), 1'500'000'000);
  EXPECT_DOUBLE_EQ(to_seconds(250 * kNsPerMillisecond), 0.25);
}

TEST(GrayImageView, StrideAddressesRows) {
  const std::uint8_t pixels[2 * 4] = {1, 2, 3, 0, 4, 5, 6, 0};
  const GrayImageView view{pixels, 3, 2, 4};
  EXPECT_EQ(view.at(2, 1), 6);
  EXPECT_EQ(view.row(1)[0], 4);
  EXPECT_FALSE(view.empty());
  EXPECT_TRUE(GrayImageView{}.empty());
}

TEST(Capacities, StateDimensionFollowsLandmarkPool) {
  static_assert(kMaxStateDim == kPoseDim + kLandmarkDim * kMaxLandmarks);
  EXPECT_EQ(kMaxLandmarks, 128);
}

}  // namespace
}  // namespace cleanslam::hal
