#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"
#include "sim_test_files.hpp"

namespace sim = cleanslam::sim_hal::sim;

namespace {

using cleanslam::sim_test::TempDir;

// A duration the path cannot fill used to stop at the path's end without a word.
TEST(SimDuration, ADurationLongerThanThePathIsRefusedWithItsEnd) {
  TempDir dir;
  auto sc = sim::load_scenario("default-room", {"duration_s=7200"});
  ASSERT_TRUE(sc.ok()) << sc.error();
  const auto r = sim::simulate(*sc, dir.str());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("default-room: duration_s 7200 s is longer than the path, which ends "
                           "at 470.9 s: set duration_s to at most 470.9, or path.repeats to 16"),
            std::string::npos)
      << r.error();
  EXPECT_FALSE(std::filesystem::exists(dir.sub("gyro.csv")));
}

TEST(SimDuration, AWaypointPathSaysOnlyItsEnd) {
  TempDir dir;
  auto sc = sim::load_scenario("home", {"duration_s=400"});
  ASSERT_TRUE(sc.ok()) << sc.error();
  const auto r = sim::simulate(*sc, dir.str());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("is longer than the path, which ends at"), std::string::npos)
      << r.error();
  EXPECT_EQ(r.error().find("path.repeats"), std::string::npos) << r.error();
}

}  // namespace
