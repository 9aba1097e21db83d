#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "calibrate_test_data.hpp"
#include "cleanslam/calibrate/mount_calibration.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"

using namespace cleanslam;
using namespace cleanslam::calibrate_test;

namespace {

// The simulator's board on the floor (first inner corner at on_floor, cols along its yaw) as the
// tool takes it: its centre and the direction of its rows.
calibrate::BoardOnFloor spot_of(const sim_hal::sim::Scenario& sc) {
  const auto& b = sc.checkerboard;
  const auto& f = *b.on_floor;
  const double yaw = f[2] * std::numbers::pi / 180.0;
  const double along = 0.5 * (b.cols - 1) * b.square_m, across = 0.5 * (b.rows - 1) * b.square_m;
  return {f[0] + std::cos(yaw) * along - std::sin(yaw) * across,
          f[1] + std::sin(yaw) * along + std::cos(yaw) * across, yaw};
}

// The camera's mount from the board on the floor, against the simulator's: position within 5 mm,
// the optical axis within 0.5 degrees; over seeds (image noise) and two spots of the board.
TEST(MountCalibration, MatchesTheSimulatorsMount) {
  const std::vector<std::vector<std::string>> spots = {{"checkerboard.on_floor=[0.40, 0.10, -90]"},
                                                       {"checkerboard.on_floor=[0.38, -0.13, 0]"}};
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    for (const auto& spot : spots) {
      TempDir dir;
      const auto sc = scenario("calibration-mount", seed, spot);
      simulated(sc, dir.str());
      const hal::Calibration truth = sim_hal::sim::calibration_of(sc);
      auto m = calibrate::calibrate_mount(
          calibrate::image_files(dir.sub("cam0/data")),
          {sc.checkerboard.cols, sc.checkerboard.rows, sc.checkerboard.square_m}, spot_of(sc),
          truth.camera);
      ASSERT_TRUE(m.ok()) << m.error();
      const auto& t = truth.camera.T_body_cam;
      const auto& e = m->T_body_cam;
      const double position = std::hypot(e[3] - t[3], e[7] - t[7], e[11] - t[11]);
      const double axis_cos = e[2] * t[2] + e[6] * t[6] + e[10] * t[10];
      const double axis_deg = std::acos(std::min(1.0, axis_cos)) * 180.0 / std::numbers::pi;
      std::printf("seed %llu, %s: position %.2f mm, optical axis %.3f deg, RMS %.3f px\n",
                  static_cast<unsigned long long>(seed), spot.front().c_str(), 1e3 * position,
                  axis_deg, m->rms_px);
      EXPECT_LT(position, 0.005) << "seed " << seed << " " << spot.front();
      EXPECT_LT(axis_deg, 0.5) << "seed " << seed << " " << spot.front();
    }
  }
}

// A board put elsewhere than said is not seen in the image: it only moves the camera (any motion
// of the board on the floor is the opposite motion of the camera). What is refused is a board
// that is not found, naming the image.
TEST(MountCalibration, RefusesAnImageWithoutTheBoardNamingIt) {
  TempDir dir;
  const auto sc = scenario("calibration-mount", 1);
  simulated(sc, dir.str());
  const auto images = calibrate::image_files(dir.sub("cam0/data"));
  auto m = calibrate::calibrate_mount(images, {10, 7, sc.checkerboard.square_m}, spot_of(sc),
                                      sim_hal::sim::calibration_of(sc).camera);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().find(images.front() + ": the 10 x 7 board's inner corners are not found"),
            std::string::npos)
      << m.error();
}

}  // namespace
