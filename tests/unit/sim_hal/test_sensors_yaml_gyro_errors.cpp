#include <gtest/gtest.h>

#include <string>

#include "cleanslam/sim_hal/dataset.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"

namespace cleanslam::sim_hal {
namespace {

TEST(SensorsYamlGyroErrors, SimulatorStatesTheScaleErrorAndBiasWalkItInjects) {
  sim::Scenario sc;
  sc.gyro.scale_error = -0.02;
  sc.gyro.bias_walk = 0.0005;
  const hal::Calibration cal = sim::calibration_of(sc);
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
  hal::Calibration cal;
  cal.gyro.scale_error = 0.01;
  std::string text = sensors_yaml_text(cal);
  const auto pos = text.find("scale_error: ");
  ASSERT_NE(pos, std::string::npos);
  text.insert(pos + 13, "-");
  const auto bad = parse_sensors_yaml(text, "s.yaml", nullptr);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("gyro.scale_error"), std::string::npos) << bad.error();
  EXPECT_NE(bad.error().find("s.yaml:"), std::string::npos) << bad.error();
}

}  // namespace
}  // namespace cleanslam::sim_hal
