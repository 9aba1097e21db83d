#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/firmware_parameters.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "text_checks.hpp"

namespace cleanslam {
namespace {

using firmware::config_text;
using firmware::ConfigResult;
using firmware::firmware_parameters;
using firmware::FirmwareConfig;
using firmware::load_config;
using firmware::parse_config;

using test::joined;

TEST(Config, TheSampleDocumentsEveryKeyWithItsDefault) {
  const std::string sample =
      std::string(CLEANSLAM_SOURCE_DIR) + "/firmware/config/cleanslam.sample.yaml";
  const ConfigResult r = load_config(sample, {});
  ASSERT_TRUE(r.ok()) << joined(r.errors);
  EXPECT_TRUE(r.warnings.empty()) << joined(r.warnings);
  EXPECT_EQ(config_text(r.config), config_text(FirmwareConfig{}));
  // And every key of the canonical text appears in the sample.
  const ConfigResult defaults = parse_config(config_text(FirmwareConfig{}), "canonical", {});
  ASSERT_TRUE(defaults.ok()) << joined(defaults.errors);
  EXPECT_TRUE(defaults.warnings.empty()) << joined(defaults.warnings);
}

TEST(Config, CanonicalTextReadsBackToTheSameConfiguration) {
  const ConfigResult a = parse_config(
      "filter:\n  eps_ct_m: 123.456789\nloop:\n  gyro_timeout_s: 0.123\nsource:\n  kind: log\n"
      "  path: \"/tmp/x y.log\"\nrecorder:\n  frame_every: 3\ncalibration:\n  camera:\n"
      "    fx: 281.25\n",
      "a.yaml", {});
  ASSERT_TRUE(a.ok()) << joined(a.errors);
  EXPECT_EQ(a.config.slam.filter.eps_ct_m, 123.456789);
  EXPECT_EQ(a.config.loop.gyro_timeout_ns, 123'000'000);
  EXPECT_EQ(a.config.source.kind, firmware::SourceSettings::Kind::kLog);
  EXPECT_EQ(a.config.source.path, "/tmp/x y.log");
  EXPECT_EQ(a.config.calibration.camera.fx, 281.25);
  const std::string text = config_text(a.config);
  const ConfigResult b = parse_config(text, "b.yaml", {});
  ASSERT_TRUE(b.ok()) << joined(b.errors);
  EXPECT_EQ(config_text(b.config), text);
}

TEST(Config, PathsWithLineBreaksAndUnprintableCharactersReadBackUnchanged) {
  // A line break, a tab, a control character, a quote and a backslash; NEL, the line separator
  // and a byte order mark (YAML folds or refuses them raw); an accented letter and an emoji.
  const std::string path =
      "a\nb\tc\x01d\"e\\f\xC2\x85g\xE2\x80\xA8h\xEF\xBB\xBFi\xC3\xA9j\xF0\x9F\x98\x80k";
  FirmwareConfig c;
  c.source.kind = firmware::SourceSettings::Kind::kLog;
  c.source.path = path;
  const std::string text = config_text(c);
  const ConfigResult back = parse_config(text, "written.yaml", {});
  ASSERT_TRUE(back.ok()) << joined(back.errors) << "\n" << text;
  EXPECT_EQ(back.config.source.path, path);
  EXPECT_EQ(config_text(back.config), text);
  // A double-quoted path over two lines is folded when read (the fuzzer's case).
  const ConfigResult folded =
      parse_config("source:\n  kind: log\n  path: \"x\n\n  y\n  z\"\n", "f.yaml", {});
  ASSERT_TRUE(folded.ok()) << joined(folded.errors);
  EXPECT_EQ(folded.config.source.path, "x\ny z");
  EXPECT_EQ(parse_config(config_text(folded.config), "w.yaml", {}).config.source.path, "x\ny z");
}

TEST(Config, WrongTypeOrRangeNamesFileLineAndKey) {
  const ConfigResult r = parse_config(
      "loop:\n  publish_rate_hz: fast\n  frame_rate_hz: 100\nfilter:\n  max_landmarks: 500\n"
      "source:\n  kind: camera\n",
      "robot.yaml", {});
  ASSERT_EQ(r.errors.size(), 4U) << joined(r.errors);
  const std::string all = joined(r.errors);
  EXPECT_NE(all.find("robot.yaml:2"), std::string::npos) << all;
  EXPECT_NE(all.find("loop.publish_rate_hz"), std::string::npos) << all;
  EXPECT_NE(all.find("robot.yaml:3: loop.frame_rate_hz: 100 is out of range"), std::string::npos)
      << all;
  EXPECT_NE(all.find("robot.yaml:5: filter.max_landmarks: 500 is out of range"), std::string::npos)
      << all;
  EXPECT_NE(all.find("robot.yaml:7: source.kind"), std::string::npos) << all;
}

// A camera mount that is not a rigid transform on the robot (a 2 in the rotation, a lever arm of
// 10000 km) is refused with the key's location: before this check, runs with either went through
// with every landmark out of the image or behind the camera.
TEST(Config, CameraMountMustBeARigidTransformOnTheRobot) {
  const auto error_of = [](const std::string& row0) {
    const ConfigResult r = parse_config("calibration:\n  camera:\n    T_body_cam: [" + row0 +
                                            ", -1, 0, 0, 0,  0, -1, 0, 0.1,  0, 0, 0, 1]\n",
                                        "robot.yaml", {});
    return joined(r.errors);
  };
  EXPECT_EQ(error_of("0, 0, 1, 0.1"), "");
  EXPECT_NE(
      error_of("0, 0, 2, 0.1")
          .find("robot.yaml:3: calibration.camera.T_body_cam: rotation block is not orthonormal"),
      std::string::npos)
      << error_of("0, 0, 2, 0.1");
  EXPECT_NE(error_of("0, 0, 1, 1e7").find("calibration.camera.T_body_cam: translation more than"),
            std::string::npos)
      << error_of("0, 0, 1, 1e7");
}

// The calibration section is checked against the same hal::calibration_limits as a dataset's
// sensors.yaml.
TEST(Config, CalibrationDistortionIsRangeChecked) {
  const ConfigResult r =
      parse_config("calibration:\n  camera:\n    distortion: [0, 1e300, 0, 0]\n", "robot.yaml", {});
  EXPECT_NE(joined(r.errors).find(
                "robot.yaml:3: calibration.camera.distortion: 1e+300 is out of range [-100, 100]"),
            std::string::npos)
      << joined(r.errors);
  EXPECT_TRUE(parse_config("calibration:\n  camera:\n    distortion: [-0.3, 0.1, 0.001, 0]\n",
                           "robot.yaml", {})
                  .ok());
}

TEST(Config, UnknownKeysAreErrorsWithTheirLocation) {
  const ConfigResult r = parse_config("loop:\n  publish_rate: 10\nfiltre: {}\n", "w.yaml", {});
  EXPECT_FALSE(r.ok());
  ASSERT_EQ(r.errors.size(), 2U) << joined(r.errors);
  const std::string all = joined(r.errors);
  EXPECT_NE(all.find("w.yaml:2"), std::string::npos) << all;
  EXPECT_NE(all.find("loop.publish_rate"), std::string::npos) << all;
  EXPECT_NE(all.find("filtre"), std::string::npos) << all;
}

// The sample's header says what the parser does with an unknown key (it once said "ignored with
// a warning").
TEST(Config, TheSampleHeaderTellsThatAnUnknownKeyStopsTheProgram) {
  const std::string sample = firmware::sample_config_text();
  const std::string head = sample.substr(0, sample.find("\n\n"));
  EXPECT_EQ(head.find("ignored"), std::string::npos) << head;
  EXPECT_NE(head.find("or an unknown key stops the program"), std::string::npos) << head;
}

TEST(Config, SetOverridesFileValuesAndCreatesSections) {
  const ConfigResult r = parse_config("loop:\n  publish_rate_hz: 10\n", "s.yaml",
                                      {"loop.publish_rate_hz=50", "recorder.path=/tmp/r.log",
                                       "calibration.camera.distortion=[0.1, 0, 0, 0]"});
  ASSERT_TRUE(r.ok()) << joined(r.errors);
  EXPECT_EQ(r.config.loop.publish_rate_hz, 50.0);
  EXPECT_EQ(r.config.recorder.path, "/tmp/r.log");
  EXPECT_EQ(r.config.calibration.camera.distortion[0], 0.1);
  const ConfigResult bad = parse_config("", "s.yaml", {"loop.gyro_timeout_s=-1"});
  ASSERT_EQ(bad.errors.size(), 1U);
  EXPECT_NE(bad.errors[0].find("--set loop.gyro_timeout_s:1: loop.gyro_timeout_s"),
            std::string::npos)
      << bad.errors[0];
  const ConfigResult malformed = parse_config("", "s.yaml", {"novalue"});
  ASSERT_EQ(malformed.errors.size(), 1U);
  EXPECT_NE(malformed.errors[0].find("novalue"), std::string::npos);
  const ConfigResult into_scalar = parse_config("loop: 3\n", "s.yaml", {"loop.x=1"});
  ASSERT_EQ(into_scalar.errors.size(), 1U) << joined(into_scalar.errors);
  EXPECT_EQ(into_scalar.errors[0], "--set loop.x: loop is not a mapping");
  const ConfigResult empty_part = parse_config("", "s.yaml", {"loop..x=1"});
  ASSERT_EQ(empty_part.errors.size(), 1U) << joined(empty_part.errors);
  EXPECT_EQ(empty_part.errors[0], "--set loop..x: empty key component");
  const ConfigResult scalar_document = parse_config("3\n", "s.yaml", {"loop.x=1", "map.y=2"});
  ASSERT_EQ(scalar_document.errors.size(), 1U) << joined(scalar_document.errors);
  EXPECT_EQ(scalar_document.errors[0], "s.yaml:1: expected a mapping, got \"3\"");
}

TEST(Config, AMissingFileIsAnErrorNamingIt) {
  const ConfigResult r = load_config("/nonexistent/robot.yaml", {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.errors[0].find("/nonexistent/robot.yaml"), std::string::npos);
}

TEST(Config, RemapKeysParseAndAreRangeChecked) {
  const ConfigResult r = parse_config(
      "map_management:\n  remap_pixel_std_px: 0\n  remap_min_yaw_std_deg: 10\n"
      "  remap_max_mapped_in_view: 4\n",
      "r.yaml", {});
  ASSERT_TRUE(r.ok()) << joined(r.errors);
  EXPECT_EQ(r.config.slam.map.remap_pixel_std_px, 0.0);
  EXPECT_EQ(r.config.slam.map.remap_min_yaw_std_deg, 10.0);
  EXPECT_EQ(r.config.slam.map.remap_max_mapped_in_view, 4);
  const ConfigResult bad = parse_config(
      "map_management:\n  remap_pixel_std_px: -1\n  remap_min_yaw_std_deg: 200\n"
      "  remap_max_mapped_in_view: -2\n",
      "b.yaml", {});
  ASSERT_EQ(bad.errors.size(), 3U) << joined(bad.errors);
  const std::string all = joined(bad.errors);
  EXPECT_NE(all.find("b.yaml:2: map_management.remap_pixel_std_px"), std::string::npos) << all;
  EXPECT_NE(all.find("b.yaml:3: map_management.remap_min_yaw_std_deg"), std::string::npos) << all;
  EXPECT_NE(all.find("b.yaml:4: map_management.remap_max_mapped_in_view"), std::string::npos)
      << all;
}

TEST(Config, CalibrationGyroErrorKeysParseAndAreRangeChecked) {
  const ConfigResult r = parse_config(
      "calibration:\n  gyro:\n    scale_error: 0.02\n    bias_walk: 0.0005\n", "g.yaml", {});
  ASSERT_TRUE(r.ok()) << joined(r.errors);
  EXPECT_EQ(r.config.calibration.gyro.scale_error, 0.02);
  EXPECT_EQ(r.config.calibration.gyro.bias_walk, 0.0005);
  const ConfigResult bad =
      parse_config("calibration:\n  gyro:\n    scale_error: 2\n", "h.yaml", {});
  ASSERT_EQ(bad.errors.size(), 1U) << joined(bad.errors);
  EXPECT_NE(bad.errors[0].find("h.yaml:3: calibration.gyro.scale_error"), std::string::npos)
      << bad.errors[0];
}

TEST(Config, WheelYawFusionKeysParseAndAreRangeChecked) {
  const ConfigResult r = parse_config(
      "odometry:\n  wheel_yaw_window_intervals: 20\n"
      "  wheel_yaw_gate_chi2: 9\n  wheel_yaw_scale_std: 0.1\n"
      "  wheel_yaw_drift_std_rad_per_m: 0.3\n  wheel_yaw_correlation_time_s: 100\n",
      "w.yaml", {});
  ASSERT_TRUE(r.ok()) << joined(r.errors);
  const slam_core::SlamConfig& f = r.config.slam;
  EXPECT_EQ(f.odometry.wheel_yaw.window_intervals, 20);
  EXPECT_EQ(f.odometry.wheel_yaw.gate_chi2, 9.0);
  EXPECT_EQ(f.odometry.wheel_yaw.scale_std, 0.1);
  EXPECT_EQ(f.odometry.wheel_yaw.drift_std_rad_per_m, 0.3);
  EXPECT_EQ(f.odometry.wheel_yaw.calibration_correlation_time_s, 100.0);
  const ConfigResult bad = parse_config(
      "odometry:\n  wheel_yaw_window_intervals: 0\n  wheel_yaw_gate_chi2: 0\n"
      "  wheel_yaw_correlation_time_s: -1\n",
      "x.yaml", {});
  ASSERT_EQ(bad.errors.size(), 3U) << joined(bad.errors);
  const std::string all = joined(bad.errors);
  EXPECT_NE(all.find("x.yaml:2: odometry.wheel_yaw_window_intervals"), std::string::npos) << all;
  EXPECT_NE(all.find("x.yaml:3: odometry.wheel_yaw_gate_chi2"), std::string::npos) << all;
  EXPECT_NE(all.find("x.yaml:4: odometry.wheel_yaw_correlation_time_s"), std::string::npos) << all;
}

// Every log recorded before the sections were renamed and the internals made constants holds
// every key of then: the sample of then (every key at its default) reads to today's defaults.
TEST(Config, TheSampleBeforeTheSectionsWereRenamedLoadsToTheSameConfiguration) {
  const ConfigResult r = load_config(
      std::string(CLEANSLAM_SOURCE_DIR) + "/tests/unit/firmware/data/sample_before_sections.yaml",
      {});
  ASSERT_TRUE(r.ok()) << joined(r.errors);
  EXPECT_EQ(config_text(r.config), config_text(FirmwareConfig{}));
  ASSERT_EQ(r.warnings.size(), 2U) << joined(r.warnings);
  EXPECT_NE(r.warnings[0].find("filter.encoder_yaw_noise_rad_per_sqrt_m is now "
                               "odometry.encoder_yaw_noise_rad_per_sqrt_m"),
            std::string::npos)
      << r.warnings[0];
  EXPECT_NE(r.warnings[1].find("at the value the firmware now always uses"), std::string::npos)
      << r.warnings[1];
}

TEST(Config, AFormerNameSetsTodaysKeyAndMayNotBeSetBesideIt) {
  const ConfigResult r = parse_config(
      "filter:\n  eps_ct_m: 40\n  wheel_yaw_scale_std: 0.1\nfrontend:\n  relocalizer:\n"
      "    min_inliers: 5\nrobot:\n  on_set_down: new_map\n",
      "old.yaml", {"filter.remap_pixel_std_px=12"});
  ASSERT_TRUE(r.ok()) << joined(r.errors);
  EXPECT_EQ(r.config.slam.filter.eps_ct_m, 40.0);
  EXPECT_EQ(r.config.slam.odometry.wheel_yaw.scale_std, 0.1);
  EXPECT_EQ(r.config.slam.relocalizer.min_inliers, 5);
  EXPECT_EQ(r.config.slam.map.on_set_down, slam_core::MapConfig::SetDown::kNewMap);
  EXPECT_EQ(r.config.slam.map.remap_pixel_std_px, 12.0);
  ASSERT_EQ(r.warnings.size(), 1U) << joined(r.warnings);
  EXPECT_NE(r.warnings[0].find("4 key(s) under a former name"), std::string::npos) << r.warnings[0];
  // Out of range under a former name: refused as today's key, at the line written.
  const ConfigResult range = parse_config("filter:\n  wheel_yaw_scale_std: 11\n", "o.yaml", {});
  ASSERT_EQ(range.errors.size(), 1U) << joined(range.errors);
  EXPECT_NE(range.errors[0].find("o.yaml:2: odometry.wheel_yaw_scale_std"), std::string::npos)
      << range.errors[0];
  const ConfigResult both = parse_config(
      "filter:\n  wheel_yaw_scale_std: 0.1\nodometry:\n  wheel_yaw_scale_std: 0.2\n", "b.yaml", {});
  ASSERT_EQ(both.errors.size(), 1U) << joined(both.errors);
  EXPECT_NE(both.errors[0].find("b.yaml:2: filter.wheel_yaw_scale_std: the former name of "
                                "odometry.wheel_yaw_scale_std, which is set too"),
            std::string::npos)
      << both.errors[0];
  const ConfigResult scalar =
      parse_config("filter:\n  wheel_yaw_scale_std: 0.1\nodometry: 3\n", "s.yaml", {});
  ASSERT_EQ(scalar.errors.size(), 1U) << joined(scalar.errors);
  EXPECT_NE(scalar.errors[0].find("s.yaml:2: filter.wheel_yaw_scale_std: the former name of "
                                  "odometry.wheel_yaw_scale_std, where odometry is not a mapping"),
            std::string::npos)
      << scalar.errors[0];
}

TEST(Config, ARemovedKeyIsReadOnlyAtTheValueTheFirmwareAlwaysUses) {
  const ConfigResult same = parse_config(
      "filter:\n  invariant_reset: true\n  remap_merge_gate_chi2: 0.0\n"
      "  max_abs_pitch_rad: 1.4\nfrontend:\n  tracker:\n    max_iterations: 20\n",
      "s.yaml", {});
  ASSERT_TRUE(same.ok()) << joined(same.errors);
  EXPECT_EQ(config_text(same.config), config_text(FirmwareConfig{}));
  ASSERT_EQ(same.warnings.size(), 1U) << joined(same.warnings);
  EXPECT_NE(same.warnings[0].find("4 former key(s)"), std::string::npos) << same.warnings[0];
  const ConfigResult off = parse_config(
      "filter:\n  invariant_reset: false\n  distance_scale_correlation_m: 5\n"
      "frontend:\n  tracker:\n    max_iterations: 30\n",
      "o.yaml", {});
  ASSERT_EQ(off.errors.size(), 3U) << joined(off.errors);
  const std::string all = joined(off.errors);
  EXPECT_NE(all.find("o.yaml:2: filter.invariant_reset: no longer a key: the firmware always "
                     "uses 1"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("o.yaml:3: filter.distance_scale_correlation_m: no longer a key: the "
                     "firmware always uses 0"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("o.yaml:6: frontend.tracker.max_iterations: no longer a key: the firmware "
                     "always uses 20"),
            std::string::npos)
      << all;
}

// The estimator's switches measured and removed (docs/experiments.md) are unknown keys now: a
// configuration that still sets one is an error naming it, with the nearest key.
TEST(Config, RemovedEstimatorSwitchesAreUnknownKeys) {
  for (const char* key :
       {"gyro_bias_state", "gyro_bias_walk", "distance_scale_state", "wheel_drift_state",
        "gyro_errors_from_calibration", "hold_heading_when_still", "second_order_yaw"}) {
    const ConfigResult r =
        parse_config(std::string("filter:\n  ") + key + ": false\n", "old.yaml", {});
    ASSERT_EQ(r.errors.size(), 1U) << key << "\n" << joined(r.errors);
    EXPECT_NE(r.errors[0].find(std::string("old.yaml:2: filter.") + key), std::string::npos)
        << r.errors[0];
    EXPECT_NE(r.errors[0].find("unknown"), std::string::npos) << r.errors[0];
  }
  const ConfigResult sink = parse_config("sinks:\n  fusion: \"f.csv\"\n", "old.yaml", {});
  ASSERT_EQ(sink.errors.size(), 1U) << joined(sink.errors);
  EXPECT_NE(sink.errors[0].find("old.yaml:2: sinks.fusion"), std::string::npos) << sink.errors[0];
}

}  // namespace
}  // namespace cleanslam

namespace cleanslam {
namespace {

using firmware::sample_config_text;

// Regenerate with `cleanslam --print-sample-config > firmware/config/cleanslam.sample.yaml`.
TEST(ParameterConfig, TheCommittedSampleIsTheOneTheTablesGenerate) {
  std::ifstream in(std::string(CLEANSLAM_SOURCE_DIR) + "/firmware/config/cleanslam.sample.yaml");
  ASSERT_TRUE(in.good());
  std::stringstream committed;
  committed << in.rdbuf();
  EXPECT_EQ(committed.str(), sample_config_text())
      << "regenerate with cleanslam --print-sample-config";
}

// A value as a configuration text writes it.
std::string value_text(hal::ParameterType type, double v) {
  switch (type) {
    case hal::ParameterType::kBool:
      return v != 0.0 ? "true" : "false";
    case hal::ParameterType::kInt:
      return std::to_string(static_cast<long long>(v));
    default:
      return std::to_string(v);
  }
}

// Every key of the tables is read from its place in the configuration (nested sections
// included), range checked, and written back by config_text.
TEST(ParameterConfig, EveryTableKeyIsSetByItsConfigurationKey) {
  for (const auto& p : slam_core::slam_parameters()) {
    const bool flag = hal::parameter_type(p) == hal::ParameterType::kBool ||
                      hal::parameter_type(p) == hal::ParameterType::kChoice;
    const double v = flag ? 1.0 - p.default_value : p.hi != p.default_value ? p.hi : p.lo + 1.0;
    ASSERT_TRUE(hal::parameter_in_range(p, v)) << p.key;
    std::string value = value_text(hal::parameter_type(p), v);
    if (hal::parameter_type(p) == hal::ParameterType::kChoice) {
      slam_core::SlamConfig probe{};
      value = std::string(p.field(probe).choices[static_cast<std::size_t>(v)]);
    }
    const std::string set = std::string(p.key) + "=" + value;
    const ConfigResult r = parse_config("", "t.yaml", {set, "loop.frame_rate_hz=2"});
    ASSERT_TRUE(r.ok()) << set << "\n" << joined(r.errors);
    EXPECT_TRUE(r.warnings.empty()) << joined(r.warnings);
    EXPECT_EQ(hal::get_parameter(p, r.config.slam),
              hal::parameter_type(p) == hal::ParameterType::kFloat
                  ? static_cast<double>(static_cast<float>(v))
                  : v)
        << p.key;
    const ConfigResult back = parse_config(config_text(r.config), "back.yaml", {});
    ASSERT_TRUE(back.ok()) << joined(back.errors);
    EXPECT_EQ(config_text(back.config), config_text(r.config)) << p.key;
    // Out of range: an error naming the file, line and key; the default stays.
    if (!flag) {
      const std::string section(p.key.substr(0, p.key.rfind('.')));
      const std::string name(p.key.substr(p.key.rfind('.') + 1));
      std::string text;
      std::string indent;
      std::size_t start = 0;
      int line = 0;
      for (auto dot = section.find('.');; dot = section.find('.', start)) {
        text += indent + section.substr(start, dot - start) + ":\n";
        indent += "  ";
        ++line;
        if (dot == std::string::npos) {
          break;
        }
        start = dot + 1;
      }
      text += indent + name + ": " + value_text(hal::parameter_type(p), p.hi * 2.0 + 1.0) + "\n";
      const ConfigResult bad = parse_config(text, "bad.yaml", {});
      ASSERT_EQ(bad.errors.size(), 1U) << text << joined(bad.errors);
      const std::string where = "bad.yaml:" + std::to_string(line + 1) + ": " + std::string(p.key);
      EXPECT_NE(bad.errors[0].find(where), std::string::npos) << bad.errors[0];
      EXPECT_NE(bad.errors[0].find("out of range"), std::string::npos) << bad.errors[0];
      EXPECT_EQ(hal::get_parameter(p, bad.config.slam), hal::stored_default(p));
    }
  }
}

// The firmware's own keys: each listed default is the struct's, and each key sets the member it
// names and no other.
TEST(ParameterConfig, EachFirmwareKeySetsTheMemberItNamesAndNoOther) {
  const FirmwareConfig defaults{};
  const auto table = firmware_parameters();
  const auto value_of = [](const hal::Parameter<FirmwareConfig>& q, const FirmwareConfig& c) {
    return hal::parameter_type(q) == hal::ParameterType::kText
               ? hal::get_text_parameter(q, c)
               : std::to_string(hal::get_parameter(q, c));
  };
  for (const auto& p : table) {
    std::vector<std::string> sets;
    std::string expected;
    switch (hal::parameter_type(p)) {
      case hal::ParameterType::kText:
        sets.push_back(std::string(p.key) + "=some/where");
        expected = "some/where";
        break;
      case hal::ParameterType::kBool:
        EXPECT_EQ(hal::get_parameter(p, defaults), p.default_value) << p.key;
        sets.push_back(std::string(p.key) + "=" + (p.default_value != 0.0 ? "false" : "true"));
        expected = std::to_string(1.0 - p.default_value);
        break;
      case hal::ParameterType::kChoice: {
        EXPECT_EQ(hal::get_parameter(p, defaults), p.default_value) << p.key;
        FirmwareConfig probe{};
        const auto names = p.field(probe).choices;
        const std::size_t other = p.default_value == 0.0 ? 1U : 0U;
        sets.push_back(std::string(p.key) + "=" + std::string(names[other]));
        expected = std::to_string(static_cast<double>(other));
        break;
      }
      default: {
        EXPECT_EQ(hal::get_parameter(p, defaults), hal::stored_default(p)) << p.key;
        const double v = p.hi != p.default_value ? p.hi : p.lo;
        ASSERT_TRUE(hal::parameter_in_range(p, v)) << p.key;
        sets.push_back(
            std::string(p.key) + "=" +
            (v == std::trunc(v) ? std::to_string(std::llround(v)) : readers::format_double(v)));
        expected = std::to_string(v);
        break;
      }
    }
    if (p.key == "source.kind") {
      sets.emplace_back("source.path=some/where");
    }
    const ConfigResult r = parse_config("", "t.yaml", sets);
    ASSERT_TRUE(r.ok()) << sets[0] << "\n" << joined(r.errors);
    EXPECT_EQ(value_of(p, r.config), expected) << p.key;
    for (const auto& q : table) {
      if (&q != &p && !(p.key == "source.kind" && q.key == "source.path")) {
        EXPECT_EQ(value_of(q, r.config), value_of(q, defaults))
            << "setting " << p.key << " changed " << q.key;
      }
    }
    const ConfigResult back = parse_config(config_text(r.config), "back.yaml", {});
    ASSERT_TRUE(back.ok()) << joined(back.errors);
    EXPECT_EQ(config_text(back.config), config_text(r.config)) << p.key;
  }
}

TEST(ParameterConfig, FrontEndKeysReachThePipelineAndUnknownNestedKeysAreErrors) {
  const ConfigResult r = parse_config(
      "frontend:\n  harris:\n    k: 0.05\n    max_corner: 3\n  tracker:\n    min_ncc: 0.7\n"
      "  landmark_book:\n    min_in_view: 3\n",
      "f.yaml", {"frontend.search_region.max_half_extent_px=25"});
  ASSERT_EQ(r.errors.size(), 1U) << joined(r.errors);
  EXPECT_NE(r.errors[0].find("f.yaml:4"), std::string::npos) << r.errors[0];
  EXPECT_NE(r.errors[0].find("frontend.harris.max_corner"), std::string::npos) << r.errors[0];
  const ConfigResult good = parse_config(
      "frontend:\n  harris:\n    k: 0.05\n  tracker:\n    min_ncc: 0.7\n"
      "  landmark_book:\n    min_in_view: 3\n",
      "f.yaml", {"frontend.search_region.max_half_extent_px=25"});
  ASSERT_TRUE(good.ok()) << joined(good.errors);
  const auto& fe = good.config.slam.frontend;
  EXPECT_EQ(fe.harris.k, 0.05F);
  EXPECT_EQ(fe.tracker.min_ncc, 0.7F);
  EXPECT_EQ(fe.book.min_in_view, 3);
  EXPECT_EQ(fe.region.max_half_extent_px, 25.0);
}

}  // namespace
}  // namespace cleanslam

namespace cleanslam {
namespace {

// Whether the member a key sets lies inside `block`, a member of `config`.
template <typename Config, typename Block>
bool sets_inside(const hal::Parameter<Config>& p, Config& config, const Block& block) {
  const auto value = reinterpret_cast<std::uintptr_t>(p.field(config).value);
  const auto begin = reinterpret_cast<std::uintptr_t>(&block);
  return value >= begin && value < begin + sizeof(Block);
}

// A section's name says what it sets: each key of a section sets a member of the struct the
// section is named after (EveryTableKeyIsSetByItsConfigurationKey and
// EachFirmwareKeySetsTheMemberItNamesAndNoOther prove that it sets its own member).
TEST(ParameterConfig, EachSectionSetsTheStructItIsNamedAfter) {
  FirmwareConfig c{};
  slam_core::SlamConfig& s = c.slam;
  for (const auto& p : slam_core::slam_parameters()) {
    const std::string_view section = p.key.substr(0, p.key.find('.'));
    const bool inside = section == "filter"           ? sets_inside(p, s, s.filter)
                        : section == "odometry"       ? sets_inside(p, s, s.odometry)
                        : section == "map_management" ? sets_inside(p, s, s.map)
                        : section == "frontend"       ? sets_inside(p, s, s.frontend)
                        : section == "relocalizer"    ? sets_inside(p, s, s.relocalizer)
                                                      : false;
    EXPECT_TRUE(inside) << p.key;
  }
  for (const auto& p : firmware_parameters()) {
    const auto dot = p.key.find('.');
    const std::string_view section = p.key.substr(0, dot);
    const bool inside = dot == std::string_view::npos
                            ? p.field(c).value == &c.calibration_from_dataset
                        : section == "loop"     ? sets_inside(p, c, c.loop)
                        : section == "source"   ? sets_inside(p, c, c.source)
                        : section == "sinks"    ? sets_inside(p, c, c.sinks)
                        : section == "recorder" ? sets_inside(p, c, c.recorder)
                        : section == "robot"    ? sets_inside(p, c, c.robot)
                        : section == "map"      ? sets_inside(p, c, c.map)
                                                : false;
    EXPECT_TRUE(inside) << p.key;
  }
}

// The sample's first part is what a robot's maker sets: at most 40 keys, each with its meaning.
TEST(ParameterConfig, TheMakersPartOfTheSampleHasAtMost40DocumentedKeys) {
  const std::string sample = firmware::sample_config_text();
  const auto one = sample.find("# Part 1:");
  const auto two = sample.find("# Part 2:");
  ASSERT_NE(one, std::string::npos);
  ASSERT_NE(two, std::string::npos);
  std::istringstream part(sample.substr(one, two - one));
  int keys = 0;
  for (std::string line; std::getline(part, line);) {
    const auto start = line.find_first_not_of(' ');
    const auto colon = line.find(": ");
    if (start == std::string::npos || line[start] == '#' || colon == std::string::npos) {
      continue;
    }
    ++keys;
    EXPECT_NE(line.find("  # ", colon), std::string::npos) << "undocumented: " << line;
  }
  EXPECT_GT(keys, 0);
  EXPECT_LE(keys, 40);
}

}  // namespace
}  // namespace cleanslam
