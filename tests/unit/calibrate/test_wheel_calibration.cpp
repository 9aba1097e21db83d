#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "calibrate_test_data.hpp"
#include "cleanslam/calibrate/wheel_calibration.hpp"

using namespace cleanslam;
using namespace cleanslam::calibrate_test;

namespace {

// Acceptance (issue 44): ticks per metre and wheel base within 0.5 % of the simulator's, on its
// straight drive and turns in place, over seeds 1-5.
TEST(WheelCalibration, MatchesTheSimulatorsTruthOverSeeds) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    TempDir dir;
    const auto sc = scenario("calibration-wheels", seed);
    const readers::Dataset d = simulated(sc, dir.str());
    calibrate::WheelCalibrationOptions o;
    o.straight_length_m = sc.path.straight_m;
    auto c = calibrate::calibrate_wheels(d, o);
    ASSERT_TRUE(c.ok()) << c.error();
    const double left = sc.robot.ticks_per_meter * (1.0 + sc.encoders.scale_error_left);
    const double right = sc.robot.ticks_per_meter * (1.0 + sc.encoders.scale_error_right);
    const double base = sc.robot.wheel_base * (1.0 + sc.encoders.wheel_base_error);
    const double e_left = relative_error(c->ticks_per_meter_left, left);
    const double e_right = relative_error(c->ticks_per_meter_right, right);
    const double e_base = relative_error(c->wheel_base_m, base);
    std::printf("seed %llu: ticks/m left %+.3f %%, right %+.3f %%, wheel base %+.3f %%\n",
                static_cast<unsigned long long>(seed), 100.0 * e_left, 100.0 * e_right,
                100.0 * e_base);
    EXPECT_LT(std::abs(e_left), 0.005) << "seed " << seed;
    EXPECT_LT(std::abs(e_right), 0.005) << "seed " << seed;
    EXPECT_LT(std::abs(e_base), 0.005) << "seed " << seed;
    EXPECT_EQ(c->turns, 2);
  }
}

// Why calibrate_wheels refuses the simulated recording (empty when it does not).
std::string refusal(const std::string& name, const std::vector<std::string>& overrides) {
  TempDir dir;
  calibrate::WheelCalibrationOptions o;
  o.straight_length_m = 3.0;
  auto c = calibrate::calibrate_wheels(simulated(scenario(name, 1, overrides), dir.str()), o);
  return c.ok() ? std::string() : c.error();
}

TEST(WheelCalibration, RefusesAShortStandstillNamingTheFile) {
  const std::string e = refusal("calibration-wheels", {"path.settle_s=1"});
  EXPECT_NE(e.find("encoders.csv"), std::string::npos) << e;
  EXPECT_NE(e.find("standstill of at least 3.0 s"), std::string::npos) << e;
}

TEST(WheelCalibration, RefusesTooLittleTurning) {
  const std::string e = refusal("calibration-wheels", {"path.spin_turns=0.25"});
  EXPECT_NE(e.find("gyro.csv"), std::string::npos) << e;
  EXPECT_NE(e.find("add up to 180 degrees"), std::string::npos) << e;
}

TEST(WheelCalibration, RefusesAStandstillWithoutADrive) {
  const std::string e = refusal("calibration-gyro", {"duration_s=20"});
  EXPECT_NE(e.find("the wheels never move"), std::string::npos) << e;
}

}  // namespace
