#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cleanslam/sim_hal/sim/renderer.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"
#include "cleanslam/sim_hal/sim/trajectory.hpp"
#include "sim_test_files.hpp"

using namespace cleanslam;
namespace sim = cleanslam::sim_hal::sim;

namespace {

using sim_test::scenario;
using sim_test::slurp;
using sim_test::TempDir;

// The wheels' calibration drive: still, straight_m ahead, spin_turns full turns each way, still
// between; it ends where the straight drive did, facing the same way.
TEST(SimCalibrationScenarios, TheWheelsDriveIsStillStraightAndTurnsEachWay) {
  const sim::Scenario sc = scenario("calibration-wheels");
  sim::Random rng(sc.seed, 2);
  const sim::PathPlan plan = sim::plan_path(sc, rng);
  const sim::Trajectory traj(plan.primitives, plan.start, sc.robot.wheel_base);
  const auto& p = sc.path;
  const double spin_s = p.spin_turns * 2.0 * std::numbers::pi / p.turn_rate;
  EXPECT_NEAR(traj.duration(), 4.0 * p.settle_s + p.straight_m / p.speed + 2.0 * spin_s, 1e-9);
  EXPECT_NEAR(traj.length(), p.straight_m, 1e-9);
  const sim::TrueState end_of_straight = traj.at(p.settle_s + p.straight_m / p.speed);
  EXPECT_NEAR(end_of_straight.position.x - plan.start.x, p.straight_m, 1e-9);
  const sim::TrueState after_left_turns =
      traj.at(2.0 * p.settle_s + p.straight_m / p.speed + spin_s);
  EXPECT_NEAR(after_left_turns.yaw - plan.start.yaw, p.spin_turns * 2.0 * std::numbers::pi, 1e-9);
  const sim::TrueState end = traj.at(traj.duration());
  EXPECT_NEAR(end.yaw, plan.start.yaw, 1e-9);
  EXPECT_NEAR(end.position.x, end_of_straight.position.x, 1e-9);
}

TEST(SimCalibrationScenarios, TheStandstillNeverMoves) {
  const sim::Scenario sc = scenario("calibration-gyro", {"duration_s=30"});
  sim::Random rng(sc.seed, 2);
  const sim::PathPlan plan = sim::plan_path(sc, rng);
  const sim::Trajectory traj(plan.primitives, plan.start, sc.robot.wheel_base);
  EXPECT_DOUBLE_EQ(traj.duration(), 30.0);
  EXPECT_DOUBLE_EQ(traj.length(), 0.0);
}

// sim_truth.yaml holds the constants the sensors really had, not the nominal ones.
TEST(SimCalibrationScenarios, TheTruthFileHoldsTheTrueConstants) {
  TempDir dir;
  const sim::Scenario sc = scenario(
      "calibration-wheels", {"encoders.scale_error_left=0.01", "encoders.wheel_base_error=0.02"});
  ASSERT_TRUE(sim::simulate(sc, dir.str()).ok());
  const std::string truth = slurp(dir.sub("sim_truth.yaml"));
  EXPECT_NE(truth.find("  ticks_per_meter_left: 4040.0 "), std::string::npos) << truth;
  EXPECT_NE(truth.find("  wheel_base: 0.2397 "), std::string::npos) << truth;
  EXPECT_NE(truth.find("  noise_density: 0.0005 "), std::string::npos) << truth;
}

// The checkerboard views are rendered through the inverse of the model that projects: a pixel's
// ray projects back onto the pixel, over the whole image, with the scenario's distortion.
TEST(SimCalibrationScenarios, PixelRaysProjectBackOntoTheirPixels) {
  const sim::Scenario sc = scenario("calibration-camera");
  for (double v = 0.0; v < sc.camera.height; v += 17.0) {
    for (double u = 0.0; u < sc.camera.width; u += 23.0) {
      double pu = 0.0, pv = 0.0;
      ASSERT_TRUE(sim::project(sc.camera, sim::pixel_ray(sc.camera, u, v), pu, pv));
      EXPECT_NEAR(pu, u, 1e-6) << u << ", " << v;
      EXPECT_NEAR(pv, v, 1e-6) << u << ", " << v;
    }
  }
}

}  // namespace
