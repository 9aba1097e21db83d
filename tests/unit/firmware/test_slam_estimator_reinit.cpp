#include <cmath>

#include <gtest/gtest.h>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/slam_estimator.hpp"

// filter.reinit_behind_camera: a tracked feature whose landmark the filter places behind the
// camera starts a new landmark from its ray instead of being rejected forever.
namespace firmware = cleanslam::firmware;
namespace hal = cleanslam::hal;
namespace lf = cleanslam::hal::log;

namespace {

constexpr hal::TimeNs kMs = hal::kNsPerMillisecond;

struct FeatureRun {
  explicit FeatureRun(bool reinit) : estimator(config(reinit)) { estimator.reset(0); }

  static firmware::FirmwareConfig config(bool reinit) {
    firmware::FirmwareConfig c;
    c.filter.reinit_behind_camera = reinit;
    return c;
  }

  // Straight ahead at 1 m/s up to t.
  void drive_to(hal::TimeNs t) {
    for (; t_ <= t; t_ += 10 * kMs) {
      hal::GyroSample g;
      g.t_ns = t_;
      estimator.add_gyro(g);
      if (t_ % (50 * kMs) == 0) {
        hal::EncoderSample e;
        e.t_ns = t_;
        e.left_ticks = static_cast<std::int32_t>(std::llround(hal::to_seconds(t_) * 4000.0));
        e.right_ticks = e.left_ticks;
        estimator.add_encoder(e);
      }
    }
  }

  // One feature, track 7, at (u, v); the status recorded for it.
  lf::UpdateStatus frame(hal::TimeNs t, double u, double v, int& slot) {
    drive_to(t);
    estimator.predict(t, true);
    feature.track_id = 7;
    feature.u_px = u;
    feature.v_px = v;
    hal::CameraFrame f;
    f.t_ns = t;
    f.features = &feature;
    f.feature_count = 1;
    estimator.begin_frame(f);
    int budget = 1000;
    while (!estimator.step_frame(budget)) {
      budget = 1000;
    }
    const lf::UpdateRecord* records = nullptr;
    EXPECT_EQ(estimator.update_records(records), 1);
    slot = records[0].slot;
    return records[0].status;
  }

  firmware::SlamEstimator estimator;
  hal::FeatureObservation feature;
  hal::TimeNs t_ = 0;
};

}  // namespace

TEST(SlamEstimatorReinit, ALandmarkLeftBehindTheCameraStartsAgainFromTheNewRay) {
  for (const bool reinit : {false, true}) {
    FeatureRun run(reinit);
    int slot = -1;
    // 24 degrees left of the optical axis, at the assumed depth of 5 m.
    ASSERT_EQ(run.frame(100 * kMs, 60.0, 119.5, slot), lf::UpdateStatus::kInitialized);
    ASSERT_GE(slot, 0);
    // 7 m further the filter's landmark is behind the camera, but the feature is still seen.
    int again = -1;
    const lf::UpdateStatus st = run.frame(7100 * kMs, 60.0, 119.5, again);
    cleanslam::slam_core::PixelPrediction p;
    if (reinit) {
      EXPECT_EQ(st, lf::UpdateStatus::kInitialized);
      ASSERT_GE(again, 0);
      EXPECT_TRUE(run.estimator.ekf().predict_pixel(again, p) && p.in_front);
      EXPECT_NEAR(p.uv.x(), 60.0, 1.0);
    } else {
      EXPECT_EQ(st, lf::UpdateStatus::kRejected);
      EXPECT_EQ(again, slot);
      EXPECT_FALSE(run.estimator.ekf().predict_pixel(again, p) && p.in_front);
    }
    EXPECT_EQ(run.estimator.ekf().landmark_count(), 1);
  }
}
