// A robot's own calibration: the keys measured on it are told apart from the sample's values, and
// the packaged configuration, which has none, is flagged as uncalibrated.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/robot_calibration.hpp"
#include "text_checks.hpp"

namespace cleanslam {
namespace {

using firmware::kMeasuredCalibrationKeys;
using firmware::load_config;
using firmware::parse_config;
using test::contains;
using test::joined;

std::vector<std::string> all_measured_keys() {
  return {kMeasuredCalibrationKeys.begin(), kMeasuredCalibrationKeys.end()};
}

TEST(RobotCalibration, MeasuredKeysLeftOutAreListedWhetherFromTheFileOrAnOverride) {
  const auto none = parse_config("source:\n  kind: drivers\n", "r.yaml", {});
  ASSERT_TRUE(none.ok()) << joined(none.errors);
  EXPECT_EQ(none.calibration_not_set, all_measured_keys());

  const auto some = parse_config(
      "calibration:\n  camera:\n    fx: 281.5\n    distortion: [0.1, 0, 0, 0]\n"
      "  wheels:\n    wheel_base: 0.24\n    distance_noise: 0.03\n",
      "r.yaml", {"calibration.gyro.noise_density=0.0007"});
  ASSERT_TRUE(some.ok()) << joined(some.errors);
  EXPECT_EQ(some.calibration_not_set,
            (std::vector<std::string>{"calibration.camera.fy", "calibration.camera.cx",
                                      "calibration.camera.cy", "calibration.camera.T_body_cam",
                                      "calibration.wheels.ticks_per_meter_left",
                                      "calibration.wheels.ticks_per_meter_right"}));

  // The sample's own values, written out, are a calibration someone set.
  const auto all = parse_config(firmware::config_text(firmware::FirmwareConfig{}), "all", {});
  ASSERT_TRUE(all.ok()) << joined(all.errors);
  EXPECT_TRUE(all.calibration_not_set.empty()) << joined(all.calibration_not_set);
}

TEST(RobotCalibration, ThePackagedRobotConfigurationIsFlaggedUncalibrated) {
  const std::string path = std::string(CLEANSLAM_SOURCE_DIR) + "/firmware/packaging/cleanslam.yaml";
  const auto packaged = load_config(path, {});
  ASSERT_TRUE(packaged.ok()) << joined(packaged.errors);
  EXPECT_TRUE(packaged.warnings.empty()) << joined(packaged.warnings);  // today's keys only
  ASSERT_EQ(packaged.config.source.kind, firmware::SourceSettings::Kind::kDrivers);
  EXPECT_EQ(packaged.calibration_not_set, all_measured_keys());

  const std::string message = firmware::uncalibrated_message(packaged.calibration_not_set, path);
  for (const char* expected : {"uncalibrated: calibration.camera.fx, calibration.camera.fy",
                               "calibration.gyro.noise_density are the sample's", "degraded",
                               "cleanslam-calibrate", "docs/bring-up.md"}) {
    EXPECT_TRUE(contains(message, expected)) << expected << "\n" << message;
  }
  EXPECT_TRUE(contains(message, path)) << message;
}

}  // namespace
}  // namespace cleanslam
