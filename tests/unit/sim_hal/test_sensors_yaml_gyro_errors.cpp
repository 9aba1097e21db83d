#include <gtest/gtest.h>

#include <string>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"

namespace cleanslam::readers {
namespace {

TEST(SensorsYamlGyroErrors, SimulatorStatesTheScaleErrorAndBiasWalkItInjects) {
  sim_hal::sim::Scenario sc;
  sc.gyro.scale_error = -0.02;
  sc.gyro.bias_walk = 0.0005;
  const hal::Calibration cal = sim_hal::sim::calibration_of(sc);
  EXPECT_DOUBLE_EQ(cal.gyro.scale_error, 0.02);
  EXPECT_DOUBLE_EQ(cal.gyro.bias_walk, 0.0005);
  const auto back = parse_sensors_yaml(sensors_yaml_text(cal), "sensors.yaml", nullptr);
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_DOUBLE_EQ(back->gyro.scale_error, 0.02);
  EXPECT_DOUBLE_EQ(back->gyro.bias_walk, 0.0005);
}

TEST(SensorsYamlGyroErrors, AbsentKeysAreZeroAndNotWritten) {
  const hal::Calibration cal;
  const std::string text = sensors_yaml_text(cal);
  EXPECT_EQ(text.find("scale_error"), std::string::npos) << text;
  EXPECT_EQ(text.find("bias_walk"), std::string::npos) << text;
  const auto back = parse_sensors_yaml(text, "sensors.yaml", nullptr);
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->gyro.scale_error, 0.0);
  EXPECT_EQ(back->gyro.bias_walk, 0.0);
}

TEST(SensorsYamlGyroErrors, ANegativeValueIsAnErrorNamingLineAndKey) {
  // The gyro mapping is the document's last: the line appended belongs to it.
  const std::string text = sensors_yaml_text(hal::Calibration{}) + "  scale_error: -0.01\n";
  const auto bad = parse_sensors_yaml(text, "s.yaml", nullptr);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("gyro.scale_error"), std::string::npos) << bad.error();
  EXPECT_NE(bad.error().find("s.yaml:"), std::string::npos) << bad.error();
  const auto good = parse_sensors_yaml(
      sensors_yaml_text(hal::Calibration{}) + "  bias_walk: 0.001\n", "s.yaml", nullptr);
  ASSERT_TRUE(good.ok()) << good.error();
  EXPECT_DOUBLE_EQ(good->gyro.bias_walk, 0.001);
}

TEST(SensorsYamlWheelScale, SimulatorStatesTheLargerWheelScaleErrorAndItRoundTrips) {
  sim_hal::sim::Scenario sc;
  sc.encoders.scale_error_left = 0.08;
  sc.encoders.scale_error_right = -0.12;
  const hal::Calibration cal = sim_hal::sim::calibration_of(sc);
  EXPECT_DOUBLE_EQ(cal.wheels.scale_error, 0.12);
  const auto back = parse_sensors_yaml(sensors_yaml_text(cal), "sensors.yaml", nullptr);
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_DOUBLE_EQ(back->wheels.scale_error, 0.12);
}

TEST(SensorsYamlWheelScale, AValueOutsideZeroToOneIsAnErrorNamingLineAndKey) {
  std::string text = sensors_yaml_text(hal::Calibration{});
  const std::string key = "  distance_noise:";
  const auto at = text.find('\n', text.find(key)) + 1;
  const auto bad = parse_sensors_yaml(text.substr(0, at) + "  scale_error: 1.5\n" + text.substr(at),
                                      "s.yaml", nullptr);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("wheels.scale_error"), std::string::npos) << bad.error();
  EXPECT_NE(bad.error().find("s.yaml:"), std::string::npos) << bad.error();
}

}  // namespace
}  // namespace cleanslam::readers
