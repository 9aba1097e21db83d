#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"
#include "sim_test_files.hpp"

// Recordings for the calibration tests: a built-in scenario simulated into a folder and read back
// with the dataset readers, as the tool reads a robot's recording.
namespace cleanslam::calibrate_test {

using sim_test::TempDir;

// A built-in scenario with the given seed.
inline sim_hal::sim::Scenario scenario(const std::string& name, std::uint64_t seed,
                                       std::vector<std::string> overrides = {}) {
  overrides.push_back("seed=" + std::to_string(seed));
  return sim_test::scenario(name, overrides);
}

inline readers::Dataset simulated(const sim_hal::sim::Scenario& sc, const std::string& folder) {
  auto sum = sim_hal::sim::simulate(sc, folder);
  EXPECT_TRUE(sum.ok()) << (sum.ok() ? "" : sum.error());
  readers::LoadOptions load;
  load.check_images = false;
  auto d = readers::load_dataset(folder, load);
  EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error());
  return *d;
}

inline double relative_error(double measured, double truth) {
  return (measured - truth) / truth;
}

}  // namespace cleanslam::calibrate_test
