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
#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/parameter_yaml.hpp"
#include "cleanslam/readers/yaml_document.hpp"
#include "parameter_sections.hpp"

namespace cleanslam::firmware {

namespace yaml = readers::yaml;

namespace {

// Typed reading with ranges: errors name the file, line and dotted key.
class Section {
 public:
  Section(yaml::MappingReader reader, yaml::Diagnostics& d) : m_(std::move(reader)), d_(d) {}

  void number(const char* key, double& v, hal::calibration_limits::Limit limit) {
    readers::read_parameter_field(m_, key, hal::parameter_field(v), limit.lo, limit.hi,
                                  limit.lo_open, "", d_);
  }
  // A number checked by the caller.
  double value(const char* key, double fallback) { return m_.optional_double(key, fallback); }
  void integer(const char* key, int& v, int lo, int hi) {
    readers::read_parameter_field(m_, key, hal::parameter_field(v), lo, hi, false, "", d_);
  }
  template <std::size_t N>
  void numbers(const char* key, std::array<double, N>& out) {
    const auto v = m_.optional_doubles(key, std::vector<double>(out.begin(), out.end()), N);
    if (v.size() == N) {
      std::copy(v.begin(), v.end(), out.begin());
    }
  }
  Section sub(const char* key) { return Section(m_.optional_mapping(key), d_); }
  // The dotted path of this section with a trailing dot ("calibration.camera.").
  [[nodiscard]] std::string prefix() const { return m_.path(""); }
  void error(const char* key, const std::string& message) {
    d_.errors.push_back(where(key) + ": " + message);
  }
  void warning(const char* key, const std::string& message) {
    d_.warnings.push_back(where(key) + ": " + message);
  }
  void done() { m_.report_unknown_keys(); }

 private:
  std::string where(const char* key) {
    const yaml::Node* n = m_.node(key);
    return (n != nullptr ? n->location.str() + ": " : std::string()) + m_.path(key);
  }
  yaml::MappingReader m_;
  yaml::Diagnostics& d_;
};

namespace lim = hal::calibration_limits;

void read_calibration(Section c, hal::Calibration& cal) {
  {
    Section cam = c.sub("camera");
    cam.integer("width", cal.camera.width, 1, hal::kImageWidth);
    cam.integer("height", cal.camera.height, 1, hal::kImageHeight);
    cal.camera.fx = cam.value("fx", cal.camera.fx);
    cal.camera.fy = cam.value("fy", cal.camera.fy);
    cal.camera.cx = cam.value("cx", cal.camera.cx);
    cal.camera.cy = cam.value("cy", cal.camera.cy);
    for (const auto& e : lim::camera_geometry_errors(cal.camera, cam.prefix())) {
      cam.error(e.key, e.message);
    }
    cam.numbers("distortion", cal.camera.distortion);
    for (const double k : cal.camera.distortion) {
      if (!lim::kDistortion.contains(k)) {
        cam.error("distortion", lim::out_of_range(k, lim::kDistortion));
        break;
      }
    }
    cam.numbers("T_body_cam", cal.camera.T_body_cam);
    if (const char* bad = hal::camera_mount_error(cal.camera.T_body_cam)) {
      cam.error("T_body_cam", bad);
    }
    cam.number("pixel_noise", cal.camera.pixel_noise, lim::kPixelNoisePx);
    cam.number("time_offset_s", cal.camera.time_offset_s, lim::kTimeOffsetS);
    if (std::abs(cal.camera.time_offset_s) > lim::kPlausibleTimeOffsetS) {
      cam.warning("time_offset_s", lim::implausible_time_offset(cal.camera.time_offset_s));
    }
    cam.done();
  }
  {
    Section w = c.sub("wheels");
    auto& wh = cal.wheels;
    w.number("ticks_per_meter_left", wh.ticks_per_meter_left, lim::kTicksPerMeter);
    w.number("ticks_per_meter_right", wh.ticks_per_meter_right, lim::kTicksPerMeter);
    w.number("wheel_base", wh.wheel_base, lim::kWheelBaseM);
    w.number("distance_noise", wh.distance_noise, lim::kFraction);
    w.number("scale_error", wh.scale_error, lim::kFraction);
    w.done();
  }
  {
    Section g = c.sub("gyro");
    g.number("noise_density", cal.gyro.noise_density, lim::kNoiseDensity);
    g.number("bias_instability", cal.gyro.bias_instability, lim::kGyroBias);
    g.number("scale_error", cal.gyro.scale_error, lim::kFraction);
    g.number("bias_walk", cal.gyro.bias_walk, lim::kGyroBias);
    g.done();
  }
  c.done();
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
  read_calibration(Section(top.optional_mapping("calibration"), d), cfg.calibration);
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
  yaml::Node* node = &root;
  std::size_t start = 0;
  while (true) {
    const auto dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? dot : dot - start);
    if (part.empty()) {
      errors.push_back(origin + ": empty key component");
      return false;
    }
    if (node->is_null()) {
      node->kind = yaml::Node::Kind::kMapping;
      node->location = value->location;
    }
    if (!node->is_mapping()) {
      errors.push_back(origin + ": " + key.substr(0, start - 1) + " is not a mapping");
      return false;
    }
    yaml::Node::Entry* entry = nullptr;
    for (auto& e : node->entries) {
      if (e.key == part) {
        entry = &e;
      }
    }
    if (entry == nullptr) {
      node->entries.push_back(yaml::Node::Entry{part, value->location, yaml::Node{}});
      entry = &node->entries.back();
    }
    if (dot == std::string::npos) {
      entry->value = *value;
      return true;
    }
    node = &entry->value;
    start = dot + 1;
  }
}

// The node at the dotted `key` below `root`, or nullptr.
const yaml::Node* find_dotted(const yaml::Node& root, std::string_view key) {
  const yaml::Node* node = &root;
  while (node != nullptr && !key.empty()) {
    const auto dot = key.find('.');
    node = node->find(key.substr(0, dot));
    key = dot == std::string_view::npos ? std::string_view() : key.substr(dot + 1);
  }
  return node;
}

ConfigResult finish(yaml::Node root, const std::vector<std::string>& overrides) {
  ConfigResult result;
  for (const auto& o : overrides) {
    apply_override(root, o, result.errors);
  }
  if (!result.ok()) {
    return result;
  }
  for (const char* key : kMeasuredCalibrationKeys) {
    const yaml::Node* n = find_dotted(root, key);
    if (n == nullptr || n->is_null()) {
      result.calibration_not_set.emplace_back(key);
    }
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
  out += "calibration:\n";
  std::istringstream cal(readers::sensors_yaml_text(c.calibration));
  for (std::string line; std::getline(cal, line);) {
    out.append("  ").append(line).append("\n");
  }
  for (const std::string& section : parameter_sections::children("")) {
    out.append(section).append(":\n");
    write_section(out, section + ".", "  ", c);
  }
  return out;
}

}  // namespace cleanslam::firmware
