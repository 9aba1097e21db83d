#include <cmath>

#include <gtest/gtest.h>

#include "feature_run.hpp"

// filter.reinit_behind_camera: a tracked feature whose landmark the filter places behind the
// camera starts a new landmark from its ray instead of being rejected forever.
namespace firmware = cleanslam::firmware;
namespace hal = cleanslam::hal;
namespace lf = cleanslam::hal::log;

namespace {

constexpr hal::TimeNs kMs = hal::kNsPerMillisecond;

firmware::FirmwareConfig config(bool reinit) {
  firmware::FirmwareConfig c;
  c.slam.map.reinit_behind_camera = reinit;
  return c;
}

// One feature, track 7, at (u, v): the status recorded for it and its slot.
lf::UpdateStatus frame(cleanslam::test::FeatureRun& run, hal::TimeNs t, double u, double v,
                       int& slot) {
  const auto records = run.frame(t, {{7, u, v}});
  EXPECT_EQ(records.size(), 1U);
  slot = records.empty() ? -1 : records[0].slot;
  return records.empty() ? lf::UpdateStatus::kSkipped : records[0].status;
}

}  // namespace

TEST(SlamEstimatorReinit, ALandmarkLeftBehindTheCameraStartsAgainFromTheNewRay) {
  for (const bool reinit : {false, true}) {
    cleanslam::test::FeatureRun run(config(reinit), 1.0);
    int slot = -1;
    // 24 degrees left of the optical axis, at the assumed depth of 5 m.
    ASSERT_EQ(frame(run, 100 * kMs, 60.0, 119.5, slot), lf::UpdateStatus::kInitialized);
    ASSERT_GE(slot, 0);
    // 7 m further the filter's landmark is behind the camera, but the feature is still seen.
    int again = -1;
    const lf::UpdateStatus st = frame(run, 7100 * kMs, 60.0, 119.5, again);
    cleanslam::slam_core::PixelPrediction p;
    if (reinit) {
      EXPECT_EQ(st, lf::UpdateStatus::kInitialized);
      ASSERT_GE(again, 0);
      EXPECT_TRUE(run.estimator.ekf().predict_pixel(again, p) && p.in_front);
      EXPECT_NEAR(p.uv.x(), 60.0, 1.0);
    } else {
      EXPECT_EQ(st, lf::UpdateStatus::kBehindCamera);
      EXPECT_EQ(again, slot);
      EXPECT_FALSE(run.estimator.ekf().predict_pixel(again, p) && p.in_front);
    }
    EXPECT_EQ(run.estimator.ekf().landmark_count(), 1);
  }
}
