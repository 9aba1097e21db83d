#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "cleanslam/hal/calibration_limits.hpp"
#include "cleanslam/hal/calibration_parameters.hpp"
#include "cleanslam/readers/bounded_file.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/parameter_yaml.hpp"
#include "cleanslam/readers/yaml_document.hpp"

namespace cleanslam::readers {
namespace {
namespace lim = hal::calibration_limits;

// The keys a dataset's sensors.yaml must give (hal::calibration_parameters() has the rest's
// defaults).
constexpr std::string_view kRequiredKeys[] = {"camera.width",
                                              "camera.height",
                                              "camera.fx",
                                              "camera.fy",
                                              "camera.cx",
                                              "camera.cy",
                                              "camera.T_body_cam",
                                              "wheels.ticks_per_meter_left",
                                              "wheels.ticks_per_meter_right",
                                              "wheels.wheel_base",
                                              "gyro.noise_density"};
}  // namespace

std::string format_double(double v) {
  // Plain decimal (shortest round trip) where it is not absurdly long, so that other YAML and
  // CSV readers (which may not take "1e-04" as a number) agree; otherwise d.ddde+XX.
  char buf[400];
  const double a = std::abs(v);
  const bool fixed = a == 0.0 || (a >= 1e-12 && a < 1e15);
  auto [ptr, ec] = fixed ? std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed)
                         : std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::scientific);
  if (ec != std::errc()) {
    return "nan";
  }
  std::string s(buf, ptr);
  if (fixed && s.find('.') == std::string::npos && s.find_first_of("ni") == std::string::npos) {
    s += ".0";
  }
  if (!fixed && s.find('.') == std::string::npos) {
    s.insert(s.find('e'), ".0");
  }
  return s;
}

Result<hal::Calibration> parse_sensors_yaml(const std::string& text, const std::string& file_name,
                                            std::vector<std::string>* warnings) {
  using R = Result<hal::Calibration>;
  auto doc = yaml::parse_string(text, file_name);
  if (!doc.ok()) {
    return R::failure(doc.error());
  }
  yaml::Diagnostics diag;
  yaml::MappingReader root(*doc, "", diag);
  if (doc->is_null()) {
    return R::failure(file_name + ":1: empty document, expected sensors");
  }
  hal::Calibration c;
  for (const char* group : {"camera", "wheels", "gyro"}) {
    yaml::MappingReader m = root.required_mapping(group);
    const std::string prefix = std::string(group) + ".";
    for (const std::string_view key : kRequiredKeys) {
      if (key.starts_with(prefix)) {
        m.required_node(key.substr(prefix.size()));
      }
    }
    read_parameters(m, hal::calibration_parameters(), prefix, c, diag);
    if (std::string_view(group) == "camera" && diag.ok()) {
      for (const auto& e : lim::camera_geometry_errors(c.camera, m.path(""))) {
        const yaml::Node* n = m.node(e.key);
        diag.errors.push_back((n != nullptr ? n->location.str() : file_name) + ": " +
                              m.path(e.key) + ": " + e.message);
      }
      if (const char* bad = hal::camera_mount_error(c.camera.T_body_cam)) {
        const yaml::Node* n = m.node("T_body_cam");
        diag.errors.push_back((n != nullptr ? n->location.str() : file_name) +
                              ": camera.T_body_cam: " + bad);
      }
      if (std::abs(c.camera.time_offset_s) > lim::kPlausibleTimeOffsetS) {
        const yaml::Node* n = m.node("time_offset_s");
        diag.warnings.push_back((n != nullptr ? n->location.str() : file_name) + ": " +
                                m.path("time_offset_s") + ": " +
                                lim::implausible_time_offset(c.camera.time_offset_s));
      }
    }
    m.report_unknown_keys();
  }
  root.report_unknown_keys();
  if (warnings != nullptr) {
    warnings->insert(warnings->end(), diag.warnings.begin(), diag.warnings.end());
  }
  if (!diag.ok()) {
    return R::failure(diag.error_text());
  }
  return c;
}

Result<hal::Calibration> read_sensors_yaml(const std::string& path,
                                           std::vector<std::string>* warnings) {
  auto doc_text = read_bounded_file(path, kYamlFileLimit);
  if (!doc_text.ok()) {
    return Result<hal::Calibration>::failure(doc_text.error());
  }
  return parse_sensors_yaml(*doc_text, path, warnings);
}

std::string sensors_yaml_text(const hal::Calibration& c) {
  const auto& cam = c.camera;
  std::string s;
  s += "camera:\n";
  s += "  width: " + std::to_string(cam.width) + "\n";
  s += "  height: " + std::to_string(cam.height) + "\n";
  s += "  fx: " + format_double(cam.fx) + "\n";
  s += "  fy: " + format_double(cam.fy) + "\n";
  s += "  cx: " + format_double(cam.cx) + "\n";
  s += "  cy: " + format_double(cam.cy) + "\n";
  s += "  distortion: [";
  for (std::size_t i = 0; i < 4; ++i) {
    s += (i ? ", " : "") + format_double(cam.distortion[i]);
  }
  s += "]\n";
  s += "  T_body_cam:\n    [";
  for (std::size_t i = 0; i < 16; ++i) {
    s += format_double(cam.T_body_cam[i]);
    if (i == 15) {
      s += "]\n";
    } else if (i % 4 == 3) {
      s += ",\n     ";
    } else {
      s += ", ";
    }
  }
  s += "  pixel_noise: " + format_double(cam.pixel_noise) + "\n";
  s += "  time_offset_s: " + format_double(cam.time_offset_s) + "\n";
  s += "wheels:\n";
  s += "  ticks_per_meter_left: " + format_double(c.wheels.ticks_per_meter_left) + "\n";
  s += "  ticks_per_meter_right: " + format_double(c.wheels.ticks_per_meter_right) + "\n";
  s += "  wheel_base: " + format_double(c.wheels.wheel_base) + "\n";
  s += "  distance_noise: " + format_double(c.wheels.distance_noise) + "\n";
  if (c.wheels.scale_error > 0.0) {
    s += "  scale_error: " + format_double(c.wheels.scale_error) + "\n";
  }
  s += "gyro:\n";
  s += "  noise_density: " + format_double(c.gyro.noise_density) + "\n";
  s += "  bias_instability: " + format_double(c.gyro.bias_instability) + "\n";
  if (c.gyro.scale_error > 0.0) {
    s += "  scale_error: " + format_double(c.gyro.scale_error) + "\n";
  }
  if (c.gyro.bias_walk > 0.0) {
    s += "  bias_walk: " + format_double(c.gyro.bias_walk) + "\n";
  }
  return s;
}

}  // namespace cleanslam::readers
