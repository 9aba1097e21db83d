#include "cleanslam/calibrate/calibration_yaml.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <utility>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/tools/output_paths.hpp"

namespace cleanslam::calibrate {
namespace {

// The key's value in flow style after its colon (a space first, or a new line); `indent` is
// the key's own.
std::string value_text(const MeasuredKey& k, const std::string& indent) {
  auto one = [&](double v) {
    return k.integer ? std::to_string(std::lround(v)) : readers::format_double(v);
  };
  std::string s = " ";
  if (k.values.size() == 1) {
    return s.append(one(k.values.front()));
  }
  // A 4 x 4 matrix (camera.T_body_cam) a row a line, as in sensors.yaml.
  const std::string next_row = k.values.size() == 16 ? ",\n" + indent + "   " : ", ";
  s = k.values.size() == 16 ? "\n" + indent + "  [" : " [";
  for (std::size_t i = 0; i < k.values.size(); ++i) {
    s += (i == 0 ? "" : (i % 4 == 0 ? next_row : ", ")) + one(k.values[i]);
  }
  return s + "]";
}

std::string comment_lines(const CalibrationResult& r) {
  std::string s;
  for (const std::string& line : r.method) {
    s += "# " + line + "\n";
  }
  return s;
}

template <std::size_t N>
bool assign(const std::vector<double>& values, std::array<double, N>& out) {
  if (values.size() != N) {
    return false;
  }
  std::copy(values.begin(), values.end(), out.begin());
  return true;
}

// Sets `k` in `c`; false when the key is not one a calibration measures.
bool apply(const MeasuredKey& k, hal::Calibration& c) {
  const std::string name = k.section + "." + k.key;
  if (name == "camera.distortion") {
    return assign(k.values, c.camera.distortion);
  }
  if (name == "camera.T_body_cam") {
    return assign(k.values, c.camera.T_body_cam);
  }
  if (k.values.size() != 1) {
    return false;
  }
  if (name == "camera.width" || name == "camera.height") {
    (name == "camera.width" ? c.camera.width : c.camera.height) =
        static_cast<int>(std::lround(k.values.front()));
    return true;
  }
  const std::pair<const char*, double*> scalars[] = {
      {"camera.fx", &c.camera.fx},
      {"camera.fy", &c.camera.fy},
      {"camera.cx", &c.camera.cx},
      {"camera.cy", &c.camera.cy},
      {"wheels.ticks_per_meter_left", &c.wheels.ticks_per_meter_left},
      {"wheels.ticks_per_meter_right", &c.wheels.ticks_per_meter_right},
      {"wheels.wheel_base", &c.wheels.wheel_base},
      {"gyro.noise_density", &c.gyro.noise_density},
      {"gyro.bias_instability", &c.gyro.bias_instability},
  };
  for (const auto& [key, field] : scalars) {
    if (name == key) {
      *field = k.values.front();
      return true;
    }
  }
  return false;
}

}  // namespace

std::string calibration_yaml_text(const CalibrationResult& r, YamlForm form) {
  const bool nested = form == YamlForm::kCalibrationSection;
  const std::string indent = nested ? "  " : "";
  std::string s = comment_lines(r);
  if (nested) {
    s += "calibration:\n";
  }
  std::string section;
  for (const MeasuredKey& k : r.keys) {
    if (k.section != section) {
      section = k.section;
      s += indent + section + ":\n";
    }
    s += indent + "  " + k.key + ":" + value_text(k, indent + "  ");
    if (!k.comment.empty()) {
      s += "  # " + k.comment;
    }
    s += "\n";
  }
  return s;
}

readers::Result<std::string> sensors_yaml_with(const std::string& base_path,
                                               const CalibrationResult& r) {
  using YamlResult = readers::Result<std::string>;
  auto base = readers::read_sensors_yaml(base_path);
  if (!base.ok()) {
    return YamlResult::failure(base.error());
  }
  hal::Calibration c = *base;
  std::string s = comment_lines(r) + "# Other keys as in " + base_path + ".\n";
  for (const MeasuredKey& k : r.keys) {
    if (!apply(k, c)) {
      return YamlResult::failure(k.section + "." + k.key + ": not a sensors.yaml key");
    }
    s += "#   " + k.section + "." + k.key + ":" + value_text(k, "#  ") +
         (k.comment.empty() ? "" : " (" + k.comment + ")") + "\n";
  }
  s += readers::sensors_yaml_text(c);
  // The result must read back: a measured value outside the format's limits is refused here.
  auto check = readers::parse_sensors_yaml(s, "the new sensors.yaml");
  if (!check.ok()) {
    return YamlResult::failure(check.error());
  }
  return s;
}

readers::Status write_calibration_file(const std::string& path, const std::string& text, bool force,
                                       const std::vector<std::string>& inputs) {
  if (readers::Status s = tools::prepare_output_file(path, force, inputs); !s) {
    return s;
  }
  std::ofstream out(path, std::ios::trunc);
  out << text;
  out.close();
  if (!out) {
    return readers::Status::failure(path + ": write error");
  }
  return {};
}

}  // namespace cleanslam::calibrate
