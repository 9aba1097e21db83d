#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/sim_math.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"

// Files of the simulator's tests: a folder per test, removed with it, and whole files read back.
namespace cleanslam::sim_test {

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            (std::string("cleanslam_sim_") + info->test_suite_name() + "_" + info->name() + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] std::string str() const { return path_.string(); }
  [[nodiscard]] std::string sub(const std::string& s) const { return (path_ / s).string(); }

 private:
  std::filesystem::path path_;
};

// A built-in scenario (or file) with overrides; a failure to load fails the test.
inline sim_hal::sim::Scenario scenario(const std::string& name,
                                       const std::vector<std::string>& overrides = {}) {
  auto sc = sim_hal::sim::load_scenario(name, overrides);
  EXPECT_TRUE(sc.ok()) << (sc.ok() ? "" : sc.error());
  return sc.ok() ? *sc : sim_hal::sim::Scenario{};
}

// Scenario overrides a, then b.
inline std::vector<std::string> with(std::vector<std::string> a,
                                     const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// The camera's pose with the body at (x, y) heading yaw on the floor.
inline sim_hal::sim::Pose3 camera_at(const sim_hal::sim::Scenario& sc, double x, double y,
                                     double yaw) {
  namespace sim = sim_hal::sim;
  return sim::compose(sim::Pose3{sim::rot_z(yaw), {x, y, 0.0}}, sim::body_to_camera(sc.camera));
}

// Why a dataset folder does not load; empty when it loads.
inline std::string load_error(const std::string& folder) {
  auto d = readers::load_dataset(folder);
  return d.ok() ? std::string() : d.error();
}

inline std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace cleanslam::sim_test
