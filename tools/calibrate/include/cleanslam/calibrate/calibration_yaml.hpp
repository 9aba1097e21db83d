#pragma once

#include <string>
#include <vector>

#include "cleanslam/readers/result.hpp"

// What a calibration writes: the keys it measured, in the schema of sensors.yaml and of the
// firmware configuration's `calibration` section (docs/dataset-format.md), with the method and
// its figures as YAML comments.
namespace cleanslam::calibrate {

struct MeasuredKey {
  std::string section;         // camera | wheels | gyro
  std::string key;             // e.g. ticks_per_meter_left
  std::vector<double> values;  // one, or a list (camera.distortion, camera.T_body_cam)
  bool integer = false;        // camera.width, camera.height
  std::string comment;
};

struct CalibrationResult {
  std::vector<std::string> method;  // comment lines: how, from what, with which figures
  std::vector<MeasuredKey> keys;
};

enum class YamlForm {
  kCalibrationSection,  // `calibration:` with the measured keys, for the firmware configuration
  kSensors,             // the measured keys at the top level, as in sensors.yaml
};

std::string calibration_yaml_text(const CalibrationResult& result, YamlForm form);

// A complete sensors.yaml: `base_path`'s with the measured keys replaced; refused, naming the key,
// when a measured value is outside the format's limits.
readers::Result<std::string> sensors_yaml_with(const std::string& base_path,
                                               const CalibrationResult& result);

// Writes `text` to `path`; an existing file only with `force` (the message names the file and the
// fix), never a file inside one of `inputs`.
readers::Status write_calibration_file(const std::string& path, const std::string& text, bool force,
                                       const std::vector<std::string>& inputs);

}  // namespace cleanslam::calibrate
