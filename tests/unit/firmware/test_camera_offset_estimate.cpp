#include "cleanslam/firmware/camera_offset_estimate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace cleanslam::firmware {
namespace {

namespace lf = hal::log;

// A robot turning to and fro on the spot (yaw = amplitude * sin(2 pi t / 6 s)), a 100 Hz gyro,
// a frame every 0.5 s whose true capture instant is its stamp plus true_offset_s, and distant
// points at camera height all round. The estimate gets the gyro as it comes and each frame's
// records 50 ms after its capture.
CameraOffsetEstimate::Result run(double true_offset_s, double configured_s, double amplitude_rad,
                                 lf::UpdateStatus status = lf::UpdateStatus::kUpdated) {
  hal::CameraCalibration cam;
  cam.time_offset_s = configured_s;
  CameraOffsetEstimate e(cam);
  const auto yaw = [&](double t) {
    return amplitude_rad * std::sin(2.0 * std::numbers::pi * t / 6.0);
  };
  const auto rate = [&](double t) {
    return amplitude_rad * 2.0 * std::numbers::pi / 6.0 *
           std::cos(2.0 * std::numbers::pi * t / 6.0);
  };
  double next_frame_s = 2.0;
  for (int k = 0; k <= 6000; ++k) {  // 60 s
    const double t = 0.01 * k;
    hal::GyroSample g;
    g.t_ns = hal::from_seconds(t);
    g.wz_rad_s = rate(t);
    e.gyro(g);
    const double capture_s = next_frame_s + true_offset_s;
    if (t < capture_s + 0.05 || next_frame_s > 55.0) {
      continue;
    }
    const double psi = yaw(capture_s);
    for (int i = 0; i < 36; ++i) {
      const double bearing = i * 2.0 * std::numbers::pi / 36.0 - psi;  // in the body
      const double forward = std::cos(bearing);
      if (forward <= 0.3) {
        continue;
      }
      // Camera: z forward, x right (body -y); a point 50 m away at camera height.
      const double u = cam.cx + cam.fx * (-std::sin(bearing) / forward);
      if (u < 0.0 || u > 319.0) {
        continue;
      }
      lf::UpdateRecord r;
      r.t_ns = hal::from_seconds(next_frame_s);
      r.track_id = i;
      r.status = status;
      r.u_px = u;
      r.v_px = cam.cy;
      e.update(r);
    }
    next_frame_s += 0.5;
  }
  return e.result();
}

TEST(CameraOffsetEstimate, SuggestsTheOffsetThatTheImageMotionShows) {
  for (const double truth : {-0.3, 0.0, 0.25}) {
    const CameraOffsetEstimate::Result r = run(truth, 0.0, 0.5);
    ASSERT_TRUE(r.measurable) << truth;
    EXPECT_NEAR(r.suggested_s, truth, 0.01) << truth;
    EXPECT_LT(r.std_s, 0.01) << truth;
    EXPECT_GT(r.pairs, 100U);
    EXPECT_EQ(r.configured_s, 0.0);
  }
}

TEST(CameraOffsetEstimate, ItsSearchIsAroundTheConfiguredOffset) {
  const CameraOffsetEstimate::Result r = run(0.0, 0.8, 0.5);
  ASSERT_TRUE(r.measurable);
  EXPECT_NEAR(r.suggested_s, 0.0, 0.01);
  EXPECT_EQ(r.configured_s, 0.8);
}

TEST(CameraOffsetEstimate, WithoutTurningTheOffsetIsNotMeasurable) {
  const CameraOffsetEstimate::Result r = run(0.2, 0.0, 0.0);
  EXPECT_GT(r.pairs, 100U);
  EXPECT_FALSE(r.measurable);
}

TEST(CameraOffsetEstimate, PointsNotMeasuredOrNewInTheirSlotAreNotPaired) {
  EXPECT_EQ(run(0.0, 0.0, 0.5, lf::UpdateStatus::kRejected).pairs, 0U);
  EXPECT_EQ(run(0.0, 0.0, 0.5, lf::UpdateStatus::kInitialized).pairs, 0U);
  EXPECT_GT(run(0.0, 0.0, 0.5, lf::UpdateStatus::kGated).pairs, 100U);
}

}  // namespace
}  // namespace cleanslam::firmware
