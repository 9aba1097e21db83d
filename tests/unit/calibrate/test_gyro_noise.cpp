#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "calibrate_test_data.hpp"
#include "cleanslam/calibrate/allan_deviation.hpp"

using namespace cleanslam;
using namespace cleanslam::calibrate_test;

namespace {

// White noise of density N sampled at 100 Hz: the Allan deviation is N / sqrt(tau).
TEST(AllanDeviation, WhiteNoiseFallsWithTheSquareRootOfTau) {
  std::mt19937_64 rng(7);
  const double density = 0.001, dt = 0.01;
  std::normal_distribution<double> white(0.0, density / std::sqrt(dt));
  std::vector<double> rates(200000);
  for (double& r : rates) {
    r = white(rng);
  }
  for (const calibrate::AllanPoint& p : calibrate::allan_deviation(rates, dt)) {
    if (p.tau_s > 2.0) {
      continue;  // fewer clusters: a larger spread
    }
    EXPECT_NEAR(p.deviation_rad_s * std::sqrt(p.tau_s), density, 0.05 * density) << p.tau_s;
  }
}

// Acceptance (issue 44): the noise density within 20 % of the simulator's on its standstill, over
// seeds 1-5; the bias within a few bias-walk steps of the truth.
TEST(GyroNoise, MatchesTheSimulatorsTruthOverSeeds) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    TempDir dir;
    const auto sc = scenario("calibration-gyro", seed, {"duration_s=600"});
    auto n = calibrate::gyro_noise(simulated(sc, dir.str()), {});
    ASSERT_TRUE(n.ok()) << n.error();
    const double e = relative_error(n->noise_density, sc.gyro.noise_density);
    const double e_fit = relative_error(n->slope_fit_density, sc.gyro.noise_density);
    std::printf("seed %llu: noise density %+.2f %% (slope fit %+.2f %%), bias %.5f rad/s\n",
                static_cast<unsigned long long>(seed), 100.0 * e, 100.0 * e_fit, n->bias_rad_s);
    EXPECT_LT(std::abs(e), 0.2) << "seed " << seed;
    EXPECT_LT(std::abs(e_fit), 0.2) << "seed " << seed;
    // The bias wanders by bias_walk * sqrt(600 s), 0.0024 rad/s (1 sigma) over the recording.
    EXPECT_NEAR(n->bias_rad_s, sc.gyro.initial_bias, 0.01) << "seed " << seed;
  }
}

TEST(GyroNoise, RefusesATooShortRecordingSayingHowLong) {
  TempDir dir;
  auto n = calibrate::gyro_noise(
      simulated(scenario("calibration-gyro", 1, {"duration_s=30"}), dir.str()), {});
  ASSERT_FALSE(n.ok());
  EXPECT_NE(n.error().find("gyro.csv: the standstill lasts 30.0 s"), std::string::npos)
      << n.error();
  EXPECT_NE(n.error().find("at least 100 s"), std::string::npos) << n.error();
}

TEST(GyroNoise, RefusesARecordingInWhichTheWheelsMove) {
  TempDir dir;
  auto n = calibrate::gyro_noise(simulated(scenario("calibration-wheels", 1), dir.str()), {});
  ASSERT_FALSE(n.ok());
  EXPECT_NE(n.error().find("encoders.csv: line"), std::string::npos) << n.error();
  EXPECT_NE(n.error().find("the wheels move"), std::string::npos) << n.error();
}

}  // namespace
