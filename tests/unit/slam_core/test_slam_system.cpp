#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "cleanslam/slam_core/map_snapshot.hpp"
#include "cleanslam/slam_core/slam_system.hpp"
#include "frontend_synthetic.hpp"
#include "time_units.hpp"

// SlamSystem, the estimation facade: the cap on landmarks in view, the set-down policies, the
// image path's dormant map after a relocalizing set-down, and the snapshot of the map a run saves.
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;
namespace lf = cleanslam::hal::log;

namespace {

using cleanslam::test::kMs;

class SlamSystemTest : public ::testing::Test {
 protected:
  void make(cs::MapConfig::SetDown policy) {
    cs::SlamConfig c;
    c.map.on_set_down = policy;
    system_ = std::make_unique<cs::SlamSystem>(calibration_, c);
    system_->reset();
    t_ = 0;
  }

  // Straight ahead at 0.2 m/s (gyro 100 Hz, encoders 20 Hz, 4000 ticks/m).
  void drive_to(hal::TimeNs end) {
    for (; t_ <= end; t_ += 10 * kMs) {
      hal::GyroSample g;
      g.t_ns = t_;
      system_->add_gyro(g);
      if (t_ % (50 * kMs) == 0) {
        hal::EncoderSample e;
        e.t_ns = t_;
        e.left_ticks = static_cast<std::int32_t>(std::llround(hal::to_seconds(t_) * 800.0));
        e.right_ticks = e.left_ticks;
        system_->add_encoder(e);
      }
    }
    system_->predict(end);
  }

  std::vector<lf::UpdateRecord> run(const hal::CameraFrame& f) {
    system_->begin_frame(f);
    int budget = 1000;
    while (!system_->step_frame(budget)) {
      budget = 1000;
    }
    const lf::UpdateRecord* r = nullptr;
    const int n = system_->update_records(r);
    return {r, r + n};
  }

  std::vector<lf::UpdateRecord> image_frame(hal::TimeNs t,
                                            const cleanslam::test::GrayImage& image) {
    drive_to(t);
    hal::CameraFrame f;
    f.t_ns = t_;
    f.image = image.view();
    return run(f);
  }

  std::vector<lf::UpdateRecord> features(hal::TimeNs t, std::vector<hal::FeatureObservation> f) {
    drive_to(t);
    hal::CameraFrame frame;
    frame.t_ns = t;
    frame.features = f.data();
    frame.feature_count = static_cast<int>(f.size());
    return run(frame);
  }

  const hal::Calibration calibration_;
  std::unique_ptr<cs::SlamSystem> system_;
  hal::TimeNs t_ = 0;
};

int count(const std::vector<lf::UpdateRecord>& r, lf::UpdateStatus s) {
  int n = 0;
  for (const auto& x : r) {
    n += x.status == s ? 1 : 0;
  }
  return n;
}

// 24 tracks on a grid of the image.
std::vector<hal::FeatureObservation> grid(std::int64_t first_id) {
  std::vector<hal::FeatureObservation> f;
  for (int i = 0; i < 24; ++i) {
    f.push_back({first_id + i, 30.0 + 40.0 * (i % 6), 40.0 + 40.0 * (i / 6)});
  }
  return f;
}

}  // namespace

TEST_F(SlamSystemTest, NewTracksAreMappedUpToTheCapOnLandmarksInView) {
  make(cs::MapConfig::SetDown::kNewMap);
  const auto r = features(500 * kMs, grid(0));
  EXPECT_EQ(count(r, lf::UpdateStatus::kInitialized), cs::MapManager::kMaxInView);
  EXPECT_EQ(count(r, lf::UpdateStatus::kSkipped), 24 - cs::MapManager::kMaxInView);
  EXPECT_EQ(system_->ekf().landmark_count(), cs::MapManager::kMaxInView);
  // The mapped ones are observed; none is left for new ones.
  const auto again = features(1000 * kMs, grid(0));
  EXPECT_EQ(count(again, lf::UpdateStatus::kInitialized), 0);
  EXPECT_EQ(system_->ekf().landmark_count(), cs::MapManager::kMaxInView);
}

TEST_F(SlamSystemTest, SetDownStartsANewMapOrKeepsItWithThePoseUncertain) {
  for (const auto policy : {cs::MapConfig::SetDown::kNewMap, cs::MapConfig::SetDown::kRelocalize}) {
    make(policy);
    features(500 * kMs, grid(0));
    features(1000 * kMs, grid(0));
    ASSERT_GT(system_->ekf().landmark_count(), 0);
    const double yaw_var = system_->ekf().pose_covariance()(5, 5);
    drive_to(1500 * kMs);
    system_->set_down(1500 * kMs);
    if (policy == cs::MapConfig::SetDown::kNewMap) {
      EXPECT_EQ(system_->ekf().landmark_count(), 0);
      EXPECT_FALSE(system_->pose_lost());
    } else {
      EXPECT_EQ(system_->ekf().landmark_count(), cs::MapManager::kMaxInView);
      const double s = 20.0 * M_PI / 180.0;
      EXPECT_GT(system_->ekf().pose_covariance()(5, 5), yaw_var + 0.9 * s * s);
      EXPECT_TRUE(system_->pose_lost());
      EXPECT_EQ(system_->map().dormant_count(), 0);  // frames with track ids find their map
      features(2000 * kMs, grid(0));
      EXPECT_FALSE(system_->pose_lost());
    }
  }
}

TEST_F(SlamSystemTest, ImageFramesLeaveTheMapDormantUntilItIsFoundAgain) {
  make(cs::MapConfig::SetDown::kRelocalize);
  const cleanslam::test::GrayImage image = cleanslam::test::render(cleanslam::test::Warp{});
  for (int k = 1; k <= 3; ++k) {
    image_frame(500 * kMs * k, image);
  }
  const int mapped = system_->ekf().landmark_count();
  ASSERT_GT(mapped, 5);
  ASSERT_GT(system_->pipeline().book().active_count(), 5);
  system_->set_down(t_);
  EXPECT_EQ(system_->map().dormant_count(), mapped);
  EXPECT_EQ(system_->pipeline().book().active_count(), 0);
  EXPECT_TRUE(system_->pose_lost());
  EXPECT_EQ(system_->ekf().landmark_count(), mapped);
  // The same view again: the map is found in it, and searched again.
  for (int k = 4; k <= 5; ++k) {
    image_frame(500 * kMs * k, image);
  }
  EXPECT_EQ(system_->relocalizations(), 1U);
  EXPECT_EQ(system_->map().dormant_count(), 0);
  EXPECT_GT(system_->pipeline().book().active_count(), 5);
  EXPECT_FALSE(system_->pose_lost());
}

TEST_F(SlamSystemTest, TheMapSnapshotHoldsEveryLandmarkWithItsTrackAndMarginal) {
  make(cs::MapConfig::SetDown::kNewMap);
  features(500 * kMs, grid(100));
  features(1000 * kMs, grid(100));
  const cs::Ekf& ekf = system_->ekf();
  ASSERT_GT(ekf.landmark_count(), 0);
  auto snapshot = std::make_unique<hal::map_file::MapSnapshot>();
  cs::snapshot_map(*system_, 1000 * kMs, *snapshot);
  EXPECT_EQ(snapshot->count, ekf.landmark_count());
  EXPECT_EQ(snapshot->saved_at_ns, 1000 * kMs);
  int k = 0;
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    if (!ekf.slot_used(s)) {
      continue;
    }
    const hal::map_file::MapLandmark& l = snapshot->landmarks[static_cast<std::size_t>(k++)];
    EXPECT_EQ(l.id, system_->map().owner(s));
    EXPECT_GE(l.id, 100);
    EXPECT_EQ(l.flags, 0U);  // feature frames carry no appearance
    const Eigen::Vector3d p = ekf.landmark(s);
    const Eigen::Matrix3d c = ekf.landmark_covariance(s);
    EXPECT_EQ(l.position_m, (std::array<double, 3>{p.x(), p.y(), p.z()}));
    EXPECT_EQ(l.covariance,
              (std::array<double, 6>{c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2)}));
    EXPECT_TRUE(hal::map_file::covariance_ok(l.covariance));
  }
}

TEST_F(SlamSystemTest, AnImageMapSnapshotKeepsEachLandmarksFirstSightingPatch) {
  make(cs::MapConfig::SetDown::kNewMap);
  const cleanslam::test::GrayImage image = cleanslam::test::render(cleanslam::test::Warp{});
  for (int k = 1; k <= 3; ++k) {
    image_frame(500 * kMs * k, image);
  }
  const cs::Ekf& ekf = system_->ekf();
  ASSERT_GT(ekf.landmark_count(), 5);
  auto snapshot = std::make_unique<hal::map_file::MapSnapshot>();
  cs::snapshot_map(*system_, t_, *snapshot);
  ASSERT_EQ(snapshot->count, ekf.landmark_count());
  int k = 0;
  int with_patch = 0;
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    if (!ekf.slot_used(s)) {
      continue;
    }
    const hal::map_file::MapLandmark& l = snapshot->landmarks[static_cast<std::size_t>(k++)];
    EXPECT_EQ(l.id, s);
    const cs::frontend::LandmarkPatch* patch = system_->pipeline().patches().get(s);
    ASSERT_NE(patch, nullptr);
    ASSERT_TRUE(patch->valid);
    EXPECT_NE(l.flags & hal::map_file::kHasPatch, 0U);
    EXPECT_EQ(l.first_depth_m, patch->first_depth_m);
    EXPECT_TRUE(std::equal(patch->pixels.begin(), patch->pixels.end(), l.patch.begin()));
    EXPECT_EQ((l.flags & hal::map_file::kHasAnchor) != 0, patch->has_anchor);
    with_patch += (l.flags & hal::map_file::kHasPatch) != 0 ? 1 : 0;
  }
  EXPECT_EQ(with_patch, snapshot->count);
}
