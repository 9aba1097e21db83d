#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "allocation_counter.hpp"
#include "cleanslam/slam_core/map_snapshot.hpp"
#include "cleanslam/slam_core/slam_system.hpp"
#include "frontend_synthetic.hpp"
#include "time_units.hpp"

// SlamSystem, the estimation facade: after construction neither kind of frame allocates, nor do
// odometry, prediction, the update in bounded parts, remapping and merging, a set-down
// (relocalized or a new map), the reports and the snapshot of the map a run saves.
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;
namespace lf = cleanslam::hal::log;

namespace {

using cleanslam::test::kMs;

// Drives straight ahead at 0.2 m/s (gyro 100 Hz, encoders 20 Hz, 4000 ticks/m) and counts.
struct Drive {
  cs::SlamSystem* system = nullptr;
  hal::TimeNs t = 0;
  int records = 0;
  int steps = 0;

  void to(hal::TimeNs end) {
    for (; t <= end; t += 10 * kMs) {
      hal::GyroSample g;
      g.t_ns = t;
      system->add_gyro(g);
      if (t % (50 * kMs) == 0) {
        hal::EncoderSample e;
        e.t_ns = t;
        e.left_ticks = static_cast<std::int32_t>(std::llround(hal::to_seconds(t) * 0.2 * 4000.0));
        e.right_ticks = e.left_ticks;
        system->add_encoder(e);
        system->predict(t);
      }
    }
  }

  void frame(const hal::CameraFrame& f) {
    system->begin_frame(f);
    int budget = 4;
    while (!system->step_frame(budget)) {
      budget = 4;
      ++steps;
    }
    const lf::UpdateRecord* r = nullptr;
    records += system->update_records(r);
  }
};

cs::SlamConfig config(cs::MapConfig::SetDown on_set_down) {
  cs::SlamConfig c;
  c.update_work_step = 20000;  // the update in many bounded parts
  c.map.on_set_down = on_set_down;
  c.map.remap_min_yaw_std_deg = 1.0;
  c.map.remap_pixel_std_px = 5.0;
  return c;
}

}  // namespace

TEST(SlamSystemAllocation, FramesWithTrackIdsAllocateNothing) {
  const hal::Calibration calibration;
  for (const auto policy : {cs::MapConfig::SetDown::kRelocalize, cs::MapConfig::SetDown::kNewMap}) {
    auto system = std::make_unique<cs::SlamSystem>(calibration, config(policy));
    std::vector<hal::FeatureObservation> features(40);
    auto snapshot = std::make_unique<hal::map_file::MapSnapshot>();
    Drive drive{system.get()};
    std::size_t allocations = 0;
    {
      Eigen::internal::set_is_malloc_allowed(false);
      const cleanslam::test::AllocationScope scope;
      system->reset();
      for (int k = 1; k <= 12; ++k) {
        drive.to(500 * kMs * k);
        if (k == 6) {
          system->set_down(drive.t);  // relocalized: remapping and merging follow
        }
        for (std::size_t i = 0; i < features.size(); ++i) {
          // After the set-down two earlier tracks among new ones (remapped), then new ones only
          // (the remapped ones merged).
          const auto id = static_cast<std::int64_t>(i);
          const std::int64_t track = k < 6 ? id % 30 : k < 9 ? (i < 2 ? id : 100 + id) : 200 + id;
          const double a = static_cast<double>(i);
          features[i] = {track, 20.0 + 7.0 * a - 0.5 * k, 30.0 + 4.0 * a + 0.3 * k};
        }
        hal::CameraFrame f;
        f.t_ns = drive.t;
        f.features = features.data();
        f.feature_count = static_cast<int>(features.size());
        drive.frame(f);
      }
      static_cast<void>(system->pose(drive.t));
      static_cast<void>(system->dead_reckoning_pose(drive.t));
      static_cast<void>(system->pose_lost());
      cs::snapshot_map(*system, drive.t, *snapshot);
      allocations = scope.count();
      Eigen::internal::set_is_malloc_allowed(true);
    }
    EXPECT_EQ(allocations, 0U);
    EXPECT_EQ(snapshot->count, system->ekf().landmark_count());
    EXPECT_GT(drive.records, 100);
    EXPECT_GT(drive.steps, 0);  // the update ran in parts
    EXPECT_GT(system->ekf().landmark_count(), 10);
    EXPECT_GT(system->ekf().counters().updates_applied, 3U);
    if (policy == cs::MapConfig::SetDown::kRelocalize) {
      EXPECT_GT(system->ekf().counters().landmarks_merged, 0U);
    }
  }
}

TEST(SlamSystemAllocation, ImageFramesAllocateNothing) {
  const hal::Calibration calibration;
  for (const auto policy : {cs::MapConfig::SetDown::kRelocalize, cs::MapConfig::SetDown::kNewMap}) {
    auto system = std::make_unique<cs::SlamSystem>(calibration, config(policy));
    std::vector<cleanslam::test::GrayImage> images;
    for (int k = 0; k < 6; ++k) {
      cleanslam::test::Warp w;
      w.scale = 1.0 + 0.02 * k;
      w.shift_x = 1.5 * k;
      images.push_back(cleanslam::test::render(w));
    }
    auto snapshot = std::make_unique<hal::map_file::MapSnapshot>();
    Drive drive{system.get()};
    std::size_t allocations = 0;
    {
      Eigen::internal::set_is_malloc_allowed(false);
      const cleanslam::test::AllocationScope scope;
      system->reset();
      for (int k = 1; k <= 12; ++k) {
        drive.to(500 * kMs * k);
        if (k == 6) {
          system->set_down(drive.t);
        }
        hal::CameraFrame f;
        f.t_ns = drive.t;
        f.image = images[static_cast<std::size_t>(k % 6)].view();
        drive.frame(f);
      }
      static_cast<void>(system->pose(drive.t));
      cs::snapshot_map(*system, drive.t, *snapshot);
      allocations = scope.count();
      Eigen::internal::set_is_malloc_allowed(true);
    }
    EXPECT_EQ(allocations, 0U);
    EXPECT_EQ(snapshot->count, system->ekf().landmark_count());
    EXPECT_EQ(system->image_frames(), 12U);
    EXPECT_GT(drive.records, 20);
    EXPECT_GT(system->ekf().counters().landmarks_initialized, 5U);
  }
}
