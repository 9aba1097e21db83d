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
