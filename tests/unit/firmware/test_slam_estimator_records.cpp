#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "cleanslam/firmware/sinks.hpp"
#include "feature_run.hpp"

// Each observation's record says why it was not fused: the depth bound and a landmark behind the
// camera have their own statuses, as the filter's rejection counters have their own reasons.
namespace firmware = cleanslam::firmware;
namespace hal = cleanslam::hal;
namespace lf = cleanslam::hal::log;
namespace cs = cleanslam::slam_core;

namespace {

using cleanslam::test::kMs;

}  // namespace

TEST(SlamEstimatorRecords, AnUpdateStoppedByTheDepthBoundIsRecordedAsSuch) {
  firmware::FirmwareConfig c;
  c.slam.filter.consider_young_landmarks = false;
  c.slam.filter.gate_chi2 = 1e9;  // wild observations pass the gate: only the bound stops them
  c.slam.filter.max_depth_m = 8.0;
  int bounded = 0;
  for (int trial = 0; trial < 4; ++trial) {
    cleanslam::test::FeatureRun run(c, 1.0);
    const double u0 = 20.0 + 30.0 * trial;  // off the direction of travel: initialized
    const auto first = run.frame(100 * kMs, {{7, u0, 120.0}});
    ASSERT_EQ(first.size(), 1U);
    ASSERT_EQ(first[0].status, lf::UpdateStatus::kInitialized);
    // After 0.4 m forward the feature has moved towards the image's centre instead of away from
    // it: a parallax that the linearized update turns into a depth beyond the room or behind the
    // camera.
    int here = 0;
    for (int k = 0; k < 4; ++k) {
      const auto records = run.frame((500 + 100 * k) * kMs, {{7, u0 + 4.0 + 4.0 * k, 120.0}});
      ASSERT_EQ(records.size(), 1U);
      EXPECT_NE(records[0].status, lf::UpdateStatus::kRejected);
      here += records[0].status == lf::UpdateStatus::kDepthBound ? 1 : 0;
    }
    const auto& counted = run.estimator.ekf().counters().rejections;
    EXPECT_EQ(counted[cs::ObservationResult::kDepthBound], static_cast<std::uint64_t>(here));
    bounded += here;
  }
  EXPECT_GT(bounded, 0);
  // The control: where the filter predicts it, the same feature is fused.
  cleanslam::test::FeatureRun run(c, 1.0);
  const auto first = run.frame(100 * kMs, {{7, 50.0, 120.0}});
  ASSERT_EQ(first.size(), 1U);
  run.frame(500 * kMs, {});
  cs::PixelPrediction p;
  ASSERT_TRUE(run.estimator.ekf().predict_pixel(first[0].slot, p));
  const auto fused = run.frame(600 * kMs, {{7, p.uv.x(), p.uv.y()}});
  ASSERT_EQ(fused.size(), 1U);
  EXPECT_EQ(fused[0].status, lf::UpdateStatus::kUpdated);
  EXPECT_STREQ(firmware::to_string(lf::UpdateStatus::kDepthBound), "depth_bound");
}

TEST(SlamEstimatorRecords, ObservationRejectionsNameTheFiltersReasons) {
  firmware::FirmwareConfig c;
  c.slam.filter.consider_young_landmarks = false;
  c.slam.filter.gate_chi2 = 1e9;
  c.slam.filter.max_depth_m = 8.0;
  cleanslam::test::FeatureRun run(c, 1.0);
  EXPECT_EQ(run.estimator.observation_rejections().count, 0);
  run.frame(100 * kMs, {{7, 40.0, 120.0}});
  for (int k = 0; k < 4; ++k) {
    run.frame((500 + 100 * k) * kMs, {{7, 44.0 + 4.0 * k, 120.0}});
  }
  const auto& counted = run.estimator.ekf().counters().rejections;
  const firmware::ObservationRejections r = run.estimator.observation_rejections();
  std::uint64_t listed = 0;
  for (int i = 0; i < r.count; ++i) {
    const auto& e = r.by_reason[static_cast<std::size_t>(i)];
    EXPECT_GT(e.count, 0U) << e.reason;
    EXPECT_STRNE(e.reason, cs::to_string(cs::ObservationResult::kFused));
    listed += e.count;
  }
  std::uint64_t total = 0;
  for (int i = 1; i < cs::kObservationResultCount; ++i) {
    total += counted.by_reason[static_cast<std::size_t>(i)];
  }
  EXPECT_EQ(listed, total);
  ASSERT_GT(counted[cs::ObservationResult::kDepthBound], 0U);
  bool named = false;
  for (int i = 0; i < r.count; ++i) {
    const auto& e = r.by_reason[static_cast<std::size_t>(i)];
    if (std::string(e.reason) == "depth_bound") {
      named = true;
      EXPECT_EQ(e.count, counted[cs::ObservationResult::kDepthBound]);
    }
  }
  EXPECT_TRUE(named);
}
