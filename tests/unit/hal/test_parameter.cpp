#include <gtest/gtest.h>

#include <set>
#include <string>

#include "cleanslam/hal/calibration_parameters.hpp"
#include "cleanslam/hal/parameter.hpp"

namespace cleanslam::hal {
namespace {

TEST(CalibrationParameters, TheStructsDefaultsAreTheListedDefaultsWithinTheirRanges) {
  const Calibration defaults{};
  std::set<std::string> keys;
  for (const auto& p : calibration_parameters()) {
    EXPECT_TRUE(keys.insert(std::string(p.key)).second) << "listed twice: " << p.key;
    if (parameter_type(p) == ParameterType::kNumbers) {
      continue;
    }
    EXPECT_EQ(get_parameter(p, defaults), stored_default(p)) << p.key;
    EXPECT_TRUE(parameter_in_range(p, p.default_value)) << p.key;
  }
}

// Each key sets the member it names and no other.
TEST(CalibrationParameters, EachKeySetsItsOwnMember) {
  const auto table = calibration_parameters();
  for (const auto& p : table) {
    if (parameter_type(p) == ParameterType::kNumbers) {
      continue;
    }
    Calibration c{};
    const double v = p.hi != p.default_value && p.hi < 1e300 ? p.hi : p.default_value + 1.0;
    set_parameter(p, c, v);
    EXPECT_EQ(get_parameter(p, c), v) << p.key;
    for (const auto& q : table) {
      if (&q != &p && parameter_type(q) != ParameterType::kNumbers) {
        EXPECT_EQ(get_parameter(q, c), stored_default(q))
            << "setting " << p.key << " changed " << q.key;
      }
    }
  }
}

struct Sizes {
  std::int64_t timeout_ns = 100'000'000;
  std::size_t buffer_bytes = 4U << 20;
  std::size_t chunk_bytes = 256U << 10;
};

// Durations and sizes are held in their own units and configured in seconds and MiB or KiB.
TEST(Parameter, ScaledFieldsConvertBetweenTheConfiguredAndTheHeldUnit) {
  const Parameter<Sizes> timeout{
      "t", [](Sizes& s) { return seconds_field(s.timeout_ns); }, 0.1, 0.001, 10.0, false, "s", ""};
  const Parameter<Sizes> buffer{
      "b", [](Sizes& s) { return mebibytes_field(s.buffer_bytes); }, 4.0, 1.0, 1e5, false, "MiB",
      ""};
  const Parameter<Sizes> chunk{
      "c", [](Sizes& s) { return kibibytes_field(s.chunk_bytes); }, 256.0, 1.0, 1e6, false, "KiB",
      ""};
  Sizes s{};
  EXPECT_EQ(get_parameter(timeout, s), 0.1);
  EXPECT_EQ(get_parameter(buffer, s), 4.0);
  EXPECT_EQ(get_parameter(chunk, s), 256.0);
  set_parameter(timeout, s, 0.25);
  set_parameter(buffer, s, 1.5);
  set_parameter(chunk, s, 3.0);
  EXPECT_EQ(s.timeout_ns, 250'000'000);
  EXPECT_EQ(s.buffer_bytes, 1572864U);
  EXPECT_EQ(s.chunk_bytes, 3072U);
  EXPECT_TRUE(parameter_in_range(buffer, 1.5));
  EXPECT_FALSE(parameter_in_range(chunk, 1.5));  // a whole number of KiB
}

}  // namespace
}  // namespace cleanslam::hal
