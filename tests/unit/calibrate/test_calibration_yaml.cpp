#include <gtest/gtest.h>

#include "cleanslam/calibrate/calibration_yaml.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"
#include "sim_test_files.hpp"

using namespace cleanslam;

namespace {

using sim_test::slurp;
using sim_test::TempDir;

calibrate::CalibrationResult wheels_result(double wheel_base) {
  calibrate::CalibrationResult r;
  r.method = {"a test: the method", "and its figures"};
  r.keys = {{"wheels", "ticks_per_meter_left", {4040.5}, false, "ticks per metre"},
            {"wheels", "wheel_base", {wheel_base}, false, "metres"}};
  return r;
}

TEST(CalibrationYaml, TheCalibrationSectionNestsTheKeysWithTheMethodInComments) {
  const std::string text = calibrate::calibration_yaml_text(
      wheels_result(0.2397), calibrate::YamlForm::kCalibrationSection);
  EXPECT_EQ(text,
            "# a test: the method\n# and its figures\ncalibration:\n  wheels:\n"
            "    ticks_per_meter_left: 4040.5  # ticks per metre\n"
            "    wheel_base: 0.2397  # metres\n");
  EXPECT_EQ(calibrate::calibration_yaml_text(wheels_result(0.2397), calibrate::YamlForm::kSensors),
            "# a test: the method\n# and its figures\nwheels:\n"
            "  ticks_per_meter_left: 4040.5  # ticks per metre\n  wheel_base: 0.2397  # metres\n");
}

TEST(CalibrationYaml, AnExistingFileIsReplacedOnlyWithForce) {
  TempDir dir;
  const std::string file = dir.sub("calibration.yaml");
  ASSERT_TRUE(calibrate::write_calibration_file(file, "a: 1\n", false, {}));
  const readers::Status again = calibrate::write_calibration_file(file, "a: 2\n", false, {});
  ASSERT_FALSE(again);
  EXPECT_EQ(again.error(), file + ": exists; choose another name, or add --force to replace it");
  EXPECT_EQ(slurp(file), "a: 1\n");
  ASSERT_TRUE(calibrate::write_calibration_file(file, "a: 2\n", true, {}));
  EXPECT_EQ(slurp(file), "a: 2\n");
}

TEST(CalibrationYaml, NeverWritesIntoTheRecording) {
  TempDir dir;
  const readers::Status s = calibrate::write_calibration_file(dir.sub("recording/out.yaml"), "",
                                                              true, {dir.sub("recording")});
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().find("recording"), std::string::npos) << s.error();
}

TEST(CalibrationYaml, ACompleteSensorsYamlFromABaseReadsBackWithTheMeasuredKeys) {
  TempDir dir;
  std::filesystem::create_directories(dir.str());
  const std::string base = dir.sub("sensors.yaml");
  {
    auto sc = sim_hal::sim::load_scenario("default-room");
    ASSERT_TRUE(sc.ok());
    std::ofstream(base) << readers::sensors_yaml_text(sim_hal::sim::calibration_of(*sc));
  }
  auto text = calibrate::sensors_yaml_with(base, wheels_result(0.2397));
  ASSERT_TRUE(text.ok()) << text.error();
  auto cal = readers::parse_sensors_yaml(*text, "new");
  ASSERT_TRUE(cal.ok()) << cal.error();
  EXPECT_DOUBLE_EQ(cal->wheels.ticks_per_meter_left, 4040.5);
  EXPECT_DOUBLE_EQ(cal->wheels.ticks_per_meter_right, 4000.0);  // the base's
  EXPECT_DOUBLE_EQ(cal->wheels.wheel_base, 0.2397);
  EXPECT_NE(text->find("# a test: the method\n"), std::string::npos);

  auto bad = calibrate::sensors_yaml_with(base, wheels_result(-1.0));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("wheels.wheel_base"), std::string::npos) << bad.error();
}

}  // namespace
