#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "feature_run.hpp"

// map_management.remap_pixel_std_px: a re-sighted landmark whose predicted pixel is too uncertain
// to linearize about is mapped again from its ray; the new entry is merged into the earlier one
// when its track ends (or its depth has converged).
namespace firmware = cleanslam::firmware;
namespace hal = cleanslam::hal;
namespace lf = cleanslam::hal::log;

namespace {

using cleanslam::test::kMs;

// Driving at 0.2 m/s.
cleanslam::test::FeatureRun remap_run(double remap_px, double min_yaw_std_deg = 0.0) {
  firmware::FirmwareConfig c;
  c.slam.map.remap_pixel_std_px = remap_px;
  c.slam.map.remap_min_yaw_std_deg = min_yaw_std_deg;
  return {c, 0.2};
}

}  // namespace

TEST(SlamEstimatorRemap, AnUncertainReSightingIsMappedAgainAndMergedWhenItsTrackEnds) {
  // A limit far below any prediction's std. dev.: every re-sighting is remapped.
  auto run = remap_run(0.01);
  auto r = run.frame(500 * kMs, {{7, 100.0, 119.5}});
  ASSERT_EQ(r.size(), 1U);
  ASSERT_EQ(r[0].status, lf::UpdateStatus::kInitialized);
  const int first = r[0].slot;
  r = run.frame(1000 * kMs, {{7, 98.0, 119.5}});
  ASSERT_EQ(r.size(), 1U);
  EXPECT_EQ(r[0].status, lf::UpdateStatus::kInitialized);
  const int second = r[0].slot;
  ASSERT_NE(second, first);
  EXPECT_EQ(run.estimator.ekf().landmark_count(), 2);
  // Track 7 is gone: its new entry joins the earlier one, which owns track 7 again.
  r = run.frame(1500 * kMs, {{8, 250.0, 119.5}});
  ASSERT_EQ(r.size(), 2U);
  EXPECT_EQ(r[0].status, lf::UpdateStatus::kMerged);
  EXPECT_EQ(r[0].track_id, 7);
  EXPECT_EQ(r[0].slot, first);
  EXPECT_EQ(r[0].mahalanobis2, run.estimator.ekf().last_merge_test_ratio());
  EXPECT_GT(r[0].mahalanobis2, 0.0);
  EXPECT_EQ(r[1].status, lf::UpdateStatus::kInitialized);
  EXPECT_TRUE(r[1].slot == second || !run.estimator.ekf().slot_used(second));
  EXPECT_EQ(run.estimator.ekf().landmark_count(), 2);
  EXPECT_EQ(run.estimator.ekf().counters().landmarks_merged, 1U);
  EXPECT_EQ(run.estimator.map_counters().merged, 1U);
  EXPECT_EQ(run.estimator.map_counters().initialized, 3U);
}

TEST(SlamEstimatorRemap, AnEarlierEntryRecycledByAFullPoolIsNotMergedInto) {
  firmware::FirmwareConfig c;
  c.slam.map.remap_pixel_std_px = 0.01;
  c.slam.map.remap_min_yaw_std_deg = 0.0;
  c.slam.filter.max_landmarks = 2;
  cleanslam::test::FeatureRun run(c, 0.2);
  auto r = run.frame(500 * kMs, {{7, 100.0, 119.5}});
  ASSERT_EQ(r.size(), 1U);
  const int first = r[0].slot;
  r = run.frame(1000 * kMs, {{7, 98.0, 119.5}});
  ASSERT_EQ(r.size(), 1U);
  const int second = r[0].slot;
  // Track 7 goes on in `second`; track 8 needs a slot: the pool (2) recycles `first`.
  r = run.frame(1500 * kMs, {{7, 96.0, 119.5}, {8, 250.0, 119.5}});
  int slot8 = -1;
  for (const auto& rec : r) {
    EXPECT_NE(rec.status, lf::UpdateStatus::kMerged);
    if (rec.track_id == 8) {
      ASSERT_EQ(rec.status, lf::UpdateStatus::kInitialized);
      slot8 = rec.slot;
    }
  }
  ASSERT_EQ(slot8, first);
  // Track 7 ends: nothing to merge it into any more; track 8 keeps its own landmark.
  r = run.frame(2000 * kMs, {{8, 248.0, 119.5}});
  for (const auto& rec : r) {
    EXPECT_NE(rec.status, lf::UpdateStatus::kMerged);
    EXPECT_NE(rec.status, lf::UpdateStatus::kMergeGated);
  }
  EXPECT_TRUE(run.estimator.ekf().slot_used(first));
  EXPECT_TRUE(run.estimator.ekf().slot_used(second));
  EXPECT_EQ(run.estimator.ekf().counters().landmarks_merged, 0U);
}

// Remapping off, or on with the default limits while the heading is known (its std. dev. after
// a second's drive is far below 3 degrees): the re-sighting updates the same slot.
TEST(SlamEstimatorRemap, OffOrWithTheHeadingKnownTheReSightingUpdatesTheSameSlot) {
  const firmware::FirmwareConfig defaults;
  for (const double remap_px : {0.0, 0.01}) {
    auto run = remap_run(remap_px, defaults.slam.map.remap_min_yaw_std_deg);
    auto r = run.frame(500 * kMs, {{7, 100.0, 119.5}});
    ASSERT_EQ(r.size(), 1U);
    const int slot = r[0].slot;
    r = run.frame(1000 * kMs, {{7, 98.0, 119.5}});
    ASSERT_EQ(r.size(), 1U);
    EXPECT_EQ(r[0].slot, slot) << remap_px;
    EXPECT_NE(r[0].status, lf::UpdateStatus::kInitialized) << remap_px;
    EXPECT_EQ(run.estimator.ekf().landmark_count(), 1);
    EXPECT_LT(std::sqrt(run.estimator.ekf().pose_covariance()(5, 5)), 3.0 * 3.14159 / 180.0);
  }
}

TEST(SlamEstimatorRemap, ThreeMappedLandmarksInViewAreUpdatedDirectly) {
  for (const int max_in_view : {2, 3}) {
    firmware::FirmwareConfig c;
    c.slam.map.remap_pixel_std_px = 0.01;
    c.slam.map.remap_min_yaw_std_deg = 0.0;
    c.slam.map.remap_max_mapped_in_view = max_in_view;
    cleanslam::test::FeatureRun run(c, 0.2);
    const std::vector<hal::FeatureObservation> three{
        {7, 100.0, 119.5}, {8, 200.0, 100.0}, {9, 250.0, 140.0}};
    auto r = run.frame(500 * kMs, three);
    ASSERT_EQ(r.size(), 3U);
    r = run.frame(1000 * kMs, {{7, 98.0, 119.5}, {8, 199.0, 100.0}, {9, 249.0, 140.0}});
    ASSERT_EQ(r.size(), 3U);
    for (const auto& rec : r) {
      EXPECT_EQ(rec.status == lf::UpdateStatus::kInitialized, max_in_view == 3)
          << "track " << rec.track_id << ", at most " << max_in_view;
    }
    EXPECT_EQ(run.estimator.ekf().landmark_count(), max_in_view == 3 ? 6 : 3);
  }
}
