#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <vector>

#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/firmware/run.hpp"
#include "fakes.hpp"

// Corrupt time stamps and clocks at the loop: each costs the sample that carries it, nothing
// overflows, and no run is held by a stamp far in the future.
namespace cleanslam {
namespace {

using firmware::Loop;
using firmware::LoopOptions;
using firmware::Reject;
using firmware::RunEnd;
using firmware::VirtualClock;
using hal::SensorEvent;

using test::kMs;
using test::kS;
using test::never_silent;
constexpr hal::TimeNs kYear = hal::TimeNs{365} * 86'400 * kS;
constexpr hal::TimeNs kNineE18 = 9'000'000'000'000'000'000;

struct FirstRejects final : firmware::HealthObserver {
  std::vector<std::pair<hal::TimeNs, Reject>> told;
  void health_changed(std::int64_t, std::uint32_t, std::uint32_t) override {}
  void first_reject(std::int64_t t_ns, Reject r) override { told.emplace_back(t_ns, r); }
};

std::size_t index_of_encoder(const test::ScriptedSource& src, int n) {
  int k = 0;
  for (std::size_t i = 0; i < src.items.size(); ++i) {
    if (src.items[i].ev.kind == SensorEvent::Kind::kEncoder && k++ == n) {
      return i;
    }
  }
  return src.items.size();
}

TEST(LoopTimeFaults, AnEncoderSampleStampedAheadCostsThatSampleOnly) {
  // Delivered on time but stamped 0.9 s ahead: within the old symmetric window of 1 s, it made
  // the next 18 good samples look out of order.
  test::FakeEstimator est;
  test::ScriptedSource src;
  src.drive(1 * kS, 4 * kS, 2.0, never_silent());
  const std::size_t k = index_of_encoder(src, 20);
  ASSERT_LT(k, src.items.size());
  src.items[k].ev.encoder.t_ns += 900 * kMs;
  Loop loop(LoopOptions{}, est);
  loop.add_source(&src);
  VirtualClock clock;
  EXPECT_EQ(firmware::run_virtual(loop, clock, false, nullptr), RunEnd::kSourcesExhausted);
  EXPECT_EQ(loop.stats().rejects[Reject::kTimeJump], 1U);
  EXPECT_EQ(loop.stats().rejects[Reject::kOutOfOrder], 0U);
  EXPECT_EQ(est.predictions, 59);  // of 60
}

TEST(LoopTimeFaults, ClocksAtTheEndsOfTimeNeitherOverflowNorPublishForever) {
  for (const hal::TimeNs jump : {kYear, kNineE18, hal::kTimeMax}) {
    test::FakeEstimator est;
    test::ScriptedSource src;
    test::CollectingSink sink;
    src.drive(1 * kS, 2 * kS, 2.0, never_silent());
    Loop loop(LoopOptions{}, est);
    loop.add_source(&src);
    loop.add_pose_sink(&sink);
    loop.start(1 * kS);
    for (hal::TimeNs t = 1 * kS; t < 2 * kS; t += 10 * kMs) {
      loop.iterate(t);
    }
    const std::size_t before = sink.poses.size();
    loop.iterate(jump);  // a clock record of a corrupt log, or a clock that jumped
    loop.iterate(jump);
    EXPECT_LE(sink.poses.size(), before + 2) << jump;
    EXPECT_GE(loop.next_deadline(), 2 * kS) << jump;
    // A sample stamped at the real time is now a time jump, not an overflow.
    src.gyro(2 * kS, 0.1);
    loop.iterate(jump);
    EXPECT_EQ(loop.stats().rejects[Reject::kTimeJump], 1U) << jump;
  }
}

TEST(LoopTimeFaults, ALoopStartedAtTheMaximumTimeStillRuns) {
  test::FakeEstimator est;
  test::ScriptedSource src;
  src.gyro(hal::kTimeMax, 0.1);
  src.gyro(hal::kTimeMin, 0.1);
  src.encoder(0, 1, 1);
  Loop loop(LoopOptions{}, est);
  loop.add_source(&src);
  loop.start(hal::kTimeMax);
  loop.iterate(hal::kTimeMax);
  loop.iterate(hal::kTimeMax);
  EXPECT_EQ(loop.stats().gyro, 2U);
  EXPECT_EQ(loop.stats().rejects[Reject::kTimeJump] + loop.stats().rejects[Reject::kOutOfOrder],
            2U);
}

TEST(LoopTimeFaults, AnEventPastTheRunsSpanIsRefusedWithoutHoldingTheRun) {
  for (const hal::TimeNs far : {2 * kS + hal::TimeNs{2} * 86'400 * kS, kNineE18, hal::kTimeMax}) {
    test::FakeEstimator est;
    test::ScriptedSource src;
    test::CollectingSink sink;
    src.drive(1 * kS, 2 * kS, 2.0, never_silent());
    src.gyro(far, 0.1);
    src.drive(2 * kS, 3 * kS, 2.0, never_silent());
    Loop loop(LoopOptions{}, est);
    loop.add_source(&src);
    loop.add_pose_sink(&sink);
    VirtualClock clock;
    EXPECT_EQ(firmware::run_virtual(loop, clock, false, nullptr), RunEnd::kSourcesExhausted);
    EXPECT_EQ(loop.stats().rejects[Reject::kTimeJump], 1U) << far;
    EXPECT_LE(sink.poses.size(), 41U) << far;
    EXPECT_EQ(est.last_gyro, 2990 * kMs) << far;
  }
}

TEST(LoopTimeFaults, FramesOfAnotherSizeThanCalibratedAreRefusedAndToldOnce) {
  test::FakeEstimator est;
  test::ScriptedSource src;
  src.drive(1 * kS, 3 * kS, 2.0, never_silent());
  const std::array<std::uint8_t, 9> tiny{};
  for (const hal::TimeNs t : {1250 * kMs, 2250 * kMs}) {
    SensorEvent ev;
    ev.kind = SensorEvent::Kind::kFrame;
    ev.frame.t_ns = t;
    ev.frame.image = hal::GrayImageView{tiny.data(), 3, 3, 3};
    // In time order, after the items due at the same time (std::stable_sort's temporary buffer
    // comes from a nothrow new that the allocation counter's delete does not pair under ASan).
    const auto at = std::upper_bound(src.items.begin(), src.items.end(), t,
                                     [](hal::TimeNs v, const auto& item) { return v < item.due; });
    src.items.insert(at, {t, ev});
  }
  Loop loop(LoopOptions{}, est);
  loop.add_source(&src);
  FirstRejects observer;
  loop.set_health_observer(&observer);
  VirtualClock clock;
  firmware::run_virtual(loop, clock, false, nullptr);
  EXPECT_EQ(loop.stats().rejects[Reject::kImageSize], 2U);
  EXPECT_EQ(loop.stats().frames_done, 4U);
  ASSERT_EQ(observer.told.size(), 1U);
  EXPECT_EQ(observer.told[0].first, 1250 * kMs);
  EXPECT_EQ(observer.told[0].second, Reject::kImageSize);
}

}  // namespace
}  // namespace cleanslam
