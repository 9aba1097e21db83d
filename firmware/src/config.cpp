#include "cleanslam/firmware/config.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>

#include "cleanslam/firmware/firmware_parameters.hpp"
#include "cleanslam/firmware/robot_calibration.hpp"
#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/calibration_limits.hpp"
#include "cleanslam/hal/calibration_parameters.hpp"
#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/parameter_yaml.hpp"
#include "cleanslam/readers/yaml_document.hpp"
#include "key_history.hpp"
#include "parameter_sections.hpp"
#include "yaml_paths.hpp"

namespace cleanslam::firmware {

namespace yaml = readers::yaml;

namespace {

namespace lim = hal::calibration_limits;

// "file:line: calibration.camera.key", or the dotted key alone when the key is absent.
std::string where(yaml::MappingReader& m, const char* key) {
  const yaml::Node* n = m.node(key);
  return (n != nullptr ? n->location.str() + ": " : std::string()) + m.path(key);
}

// The calibration section through hal::calibration_parameters(), then the camera's size,
// intrinsics and mount together.
void read_calibration(yaml::MappingReader c, hal::Calibration& cal, yaml::Diagnostics& d) {
  for (const char* group : {"camera", "wheels", "gyro"}) {
    yaml::MappingReader m = c.optional_mapping(group);
    readers::read_parameters(m, hal::calibration_parameters(), std::string(group) + ".", cal, d);
    if (std::string_view(group) == "camera") {
      for (const auto& e : lim::camera_geometry_errors(cal.camera, m.path(""))) {
        d.errors.push_back(where(m, e.key) + ": " + e.message);
      }
      if (const char* bad = hal::camera_mount_error(cal.camera.T_body_cam)) {
        d.errors.push_back(where(m, "T_body_cam") + ": " + bad);
      }
      if (std::abs(cal.camera.time_offset_s) > lim::kPlausibleTimeOffsetS) {
        d.warnings.push_back(where(m, "time_offset_s") + ": " +
                             lim::implausible_time_offset(cal.camera.time_offset_s));
      }
    }
    m.report_unknown_keys();
  }
  c.report_unknown_keys();
}

// The keys of both tables below `prefix`, nested mappings included.
void read_section(yaml::MappingReader& m, const std::string& prefix, FirmwareConfig& cfg,
                  yaml::Diagnostics& d) {
  readers::read_parameters(m, slam_core::slam_parameters(), prefix, cfg.slam, d);
  readers::read_parameters(m, firmware_parameters(), prefix, cfg, d);
  for (const std::string& child : parameter_sections::children(prefix)) {
    yaml::MappingReader sub = m.optional_mapping(child);
    read_section(sub, prefix + child + ".", cfg, d);
    sub.report_unknown_keys();
  }
}

void write_section(std::string& out, const std::string& prefix, const std::string& indent,
                   const FirmwareConfig& c) {
  readers::write_parameters(out, slam_core::slam_parameters(), prefix, indent, c.slam, false);
  readers::write_parameters(out, firmware_parameters(), prefix, indent, c, false);
  for (const std::string& child : parameter_sections::children(prefix)) {
    out.append(indent).append(child).append(":\n");
    write_section(out, prefix + child + ".", indent + "  ", c);
  }
}

void read_all(const yaml::Node& root, yaml::Diagnostics& d, FirmwareConfig& cfg) {
  yaml::MappingReader top(root, "", d);
  read_calibration(top.optional_mapping("calibration"), cfg.calibration, d);
  read_section(top, "", cfg, d);
  top.report_unknown_keys();
  const SourceSettings& source = cfg.source;
  if (source.kind != SourceSettings::Kind::kDrivers && source.path.empty()) {
    const char* kind = source.kind == SourceSettings::Kind::kDataset ? "dataset" : "log";
    const yaml::Node* section = top.node("source");
    const yaml::Node* n = section != nullptr ? section->find("path") : nullptr;
    n = n != nullptr ? n : section;
    d.errors.push_back((n != nullptr ? n->location.str() + ": " : std::string()) +
                       "source.path: a " + kind + " source needs a path");
  }
}

// "a.b.c=value": sets the node at a.b.c (creating mappings on the way) to the parsed value.
bool apply_override(yaml::Node& root, const std::string& item, std::vector<std::string>& errors) {
  const auto eq = item.find('=');
  if (eq == std::string::npos || eq == 0) {
    errors.push_back("--set " + item + ": expected key=value");
    return false;
  }
  const std::string key = item.substr(0, eq);
  const std::string origin = "--set " + key;
  auto value = yaml::parse_string(item.substr(eq + 1), origin);
  if (!value.ok()) {
    errors.push_back(value.error());
    return false;
  }
  if (value->is_null()) {
    value->kind = yaml::Node::Kind::kScalar;  // "key=" sets an empty string
    value->location.file = std::make_shared<const std::string>(origin);
    value->location.line = 1;
  }
  std::string error;
  yaml::Node* slot = yaml_paths::make(root, key, value->location, error);
  if (slot == nullptr) {
    errors.push_back(origin + ": " + error);
    return false;
  }
  *slot = *value;
  return true;
}

ConfigResult finish(yaml::Node root, const std::vector<std::string>& overrides) {
  ConfigResult result;
  // A document that is not a mapping of sections takes no override: read_all says what it is.
  if (root.is_null() || root.is_mapping()) {
    for (const auto& o : overrides) {
      apply_override(root, o, result.errors);
    }
  }
  if (!result.ok()) {
    return result;
  }
  for (const char* key : kMeasuredCalibrationKeys) {
    const yaml::Node* n = yaml_paths::find(root, key);
    if (n == nullptr || n->is_null()) {
      result.calibration_not_set.emplace_back(key);
    }
  }
  key_history::apply(root, result.errors, result.warnings);
  if (!result.ok()) {
    return result;
  }
  yaml::Diagnostics d;
  if (!root.is_null()) {
    read_all(root, d, result.config);
  }
  result.errors.insert(result.errors.end(), d.errors.begin(), d.errors.end());
  result.warnings.insert(result.warnings.end(), d.warnings.begin(), d.warnings.end());
  return result;
}

}  // namespace

ConfigResult parse_config(const std::string& text, const std::string& file_name,
                          const std::vector<std::string>& overrides) {
  auto doc = yaml::parse_string(text, file_name);
  if (!doc.ok()) {
    ConfigResult r;
    r.errors.push_back(doc.error());
    return r;
  }
  return finish(std::move(doc.value()), overrides);
}

ConfigResult load_config(const std::string& path, const std::vector<std::string>& overrides) {
  if (path.empty()) {
    return finish(yaml::Node{}, overrides);
  }
  auto doc = yaml::parse_file(path);
  if (!doc.ok()) {
    ConfigResult r;
    r.errors.push_back(doc.error());
    return r;
  }
  return finish(std::move(doc.value()), overrides);
}

std::string config_text(const FirmwareConfig& c) {
  std::string out;
  readers::write_parameters(out, firmware_parameters(), "", "", c, false);
  parameter_sections::write_calibration(out, c.calibration, false);
  for (const std::string& section : parameter_sections::children("")) {
    out.append(section).append(":\n");
    write_section(out, section + ".", "  ", c);
  }
  return out;
}

}  // namespace cleanslam::firmware
