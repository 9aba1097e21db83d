#pragma once

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "cleanslam/calibrate/camera_calibration.hpp"
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

// The scenario's checkerboard, as the calibration takes it.
inline calibrate::Checkerboard board_of(const sim_hal::sim::Scenario& sc) {
  return {sc.checkerboard.cols, sc.checkerboard.rows, sc.checkerboard.square_m};
}

// fx, fy, cx, cy's relative errors against the scenario's camera.
inline std::array<double, 4> intrinsics_errors(const calibrate::CameraCalibration& c,
                                               const sim_hal::sim::Scenario& sc) {
  const auto& t = sc.camera;
  return {relative_error(c.fx, t.fx), relative_error(c.fy, t.fy), relative_error(c.cx, t.cx),
          relative_error(c.cy, t.cy)};
}

}  // namespace cleanslam::calibrate_test
