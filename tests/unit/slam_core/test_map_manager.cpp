#include <array>
#include <span>

#include <gtest/gtest.h>

#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/map_manager.hpp"

// MapManager: a track's landmark slot, remapping an uncertain re-sighting and merging it into its
// earlier entry, re-initialization behind the camera, the cap on landmarks in view.
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

using Sighting = cs::MapManager::Sighting;

class MapManagerTest : public ::testing::Test {
 protected:
  explicit MapManagerTest(const cs::MapConfig& config = {})
      : ekf_(calibration_, cs::EkfConfig{}), map_(ekf_, config) {
    cs::Matrix6d P0 = cs::Matrix6d::Identity() * 1e-6;
    EXPECT_TRUE(ekf_.reset(cs::Vector6d::Zero(), P0));
  }

  // The camera moves `forward_m` along its optical axis (the filter frame's x).
  void move(double forward_m) {
    cs::OdometryIncrement u;
    u.dx_c = Eigen::Vector3d(forward_m, 0.0, 0.0);
    u.Q = cs::Matrix6d::Identity() * 1e-8;
    ekf_.predict(u);
  }

  hal::Calibration calibration_;
  cs::Ekf ekf_;
  cs::MapManager map_;
};

cs::MapConfig remap_config() {
  cs::MapConfig c;
  c.remap_pixel_std_px = 0.01;  // every re-sighting's prediction is too uncertain
  c.remap_min_yaw_std_deg = 0.0;
  return c;
}

class MapManagerRemapTest : public MapManagerTest {
 protected:
  MapManagerRemapTest() : MapManagerTest(remap_config()) {}
};

}  // namespace

TEST_F(MapManagerTest, ATracksLandmarkIsFoundByItsIdUntilRemovedOrForgotten) {
  const int a = map_.initialize(7, 160.0, 120.0, -1);
  const int b = map_.initialize(9, 100.0, 100.0, -1);
  ASSERT_GE(a, 0);
  ASSERT_GE(b, 0);
  EXPECT_EQ(map_.slot_of(7), a);
  EXPECT_EQ(map_.slot_of(9), b);
  EXPECT_EQ(map_.slot_of(8), -1);
  EXPECT_EQ(map_.owner(a), 7);
  int earlier = 0;
  map_.begin_frame(2);
  EXPECT_EQ(map_.classify(a, earlier), Sighting::kObserve);
  EXPECT_EQ(earlier, -1);
  EXPECT_EQ(map_.classify(-1, earlier), Sighting::kNew);
  EXPECT_EQ(earlier, -1);
  ekf_.delete_landmark(a);
  map_.remove(a);
  EXPECT_EQ(map_.slot_of(7), -1);
  map_.forget();
  EXPECT_EQ(map_.slot_of(9), -1);
}

TEST_F(MapManagerTest, ATrackerSlotOwnsItsOwnLandmark) {
  const int s = map_.initialize(cs::MapManager::kTrackerSlot, 160.0, 120.0, -1);
  ASSERT_GE(s, 0);
  EXPECT_EQ(map_.owner(s), s);
  EXPECT_EQ(map_.slot_of(s), s);
}

TEST_F(MapManagerTest, NewLandmarksFillTheViewUpToTheCap) {
  EXPECT_EQ(cs::MapManager::new_landmark_budget(0), cs::MapManager::kMaxInView);
  EXPECT_EQ(cs::MapManager::new_landmark_budget(cs::MapManager::kMaxInView - 3), 3);
  EXPECT_LE(cs::MapManager::new_landmark_budget(cs::MapManager::kMaxInView), 0);
}

TEST_F(MapManagerRemapTest, AnUncertainReSightingIsMappedAgainAndMergedIntoItsEarlierEntry) {
  const int first = map_.initialize(7, 100.0, 120.0, -1);
  ASSERT_GE(first, 0);
  move(0.5);
  map_.begin_frame(1);
  int earlier = -1;
  ASSERT_EQ(map_.classify(first, earlier), Sighting::kNew);
  EXPECT_EQ(earlier, first);
  const int second = map_.initialize(7, 98.0, 120.0, earlier);
  ASSERT_GE(second, 0);
  ASSERT_NE(second, first);
  EXPECT_EQ(map_.earlier(second), first);
  EXPECT_EQ(map_.slot_of(7), second);
  EXPECT_EQ(map_.owner(first), -1);
  // A remapped slot is not remapped again while its merge is pending.
  map_.begin_frame(1);
  EXPECT_EQ(map_.classify(second, earlier), Sighting::kObserve);
  // Still observed with its depth unknown: no merge yet.
  const std::array<cs::Observation, 1> seen{cs::Observation{second, 98.0, 120.0}};
  map_.merge_remapped(seen);
  EXPECT_EQ(map_.merge_count(), 0);
  // Its track ended: merged into the earlier entry, which owns the track again.
  map_.merge_remapped({});
  ASSERT_EQ(map_.merge_count(), 1);
  EXPECT_TRUE(map_.merge(0).merged);
  EXPECT_EQ(map_.merge(0).track, 7);
  EXPECT_EQ(map_.merge(0).slot, first);
  EXPECT_EQ(map_.merge(0).test_ratio, ekf_.last_merge_test_ratio());
  EXPECT_EQ(map_.slot_of(7), first);
  EXPECT_FALSE(ekf_.slot_used(second));
  EXPECT_EQ(ekf_.counters().landmarks_merged, 1U);
}

TEST_F(MapManagerRemapTest, EnoughMappedLandmarksInViewAreObservedDirectly) {
  const int first = map_.initialize(7, 100.0, 120.0, -1);
  move(0.5);
  map_.begin_frame(cs::MapConfig{}.remap_max_mapped_in_view + 1);
  int earlier = -1;
  EXPECT_EQ(map_.classify(first, earlier), Sighting::kObserve);
}

TEST_F(MapManagerRemapTest, AMergeIntoARemovedEarlierEntryIsDropped) {
  const int first = map_.initialize(7, 100.0, 120.0, -1);
  move(0.5);
  map_.begin_frame(1);
  int earlier = -1;
  ASSERT_EQ(map_.classify(first, earlier), Sighting::kNew);
  const int second = map_.initialize(7, 98.0, 120.0, earlier);
  ekf_.delete_landmark(first);
  map_.remove(first);
  EXPECT_EQ(map_.earlier(second), -1);
  map_.merge_remapped({});
  EXPECT_EQ(map_.merge_count(), 0);
  EXPECT_TRUE(ekf_.slot_used(second));
}
