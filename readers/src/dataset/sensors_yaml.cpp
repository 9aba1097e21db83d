#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "cleanslam/hal/calibration_limits.hpp"
#include "cleanslam/readers/bounded_file.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/yaml_document.hpp"

namespace cleanslam::readers {
namespace {
namespace lim = hal::calibration_limits;
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
  // A number outside its hal::calibration_limits is an error naming line and key.
  const auto check = [&diag](yaml::MappingReader& m, const char* key, lim::Limit limit) {
    const yaml::Node* n = m.node(key);
    auto v = n != nullptr ? yaml::as_double(*n, m.path(key)) : Result<double>(limit.hi);
    if (v.ok() && !limit.contains(*v)) {
      diag.errors.push_back(n->location.str() + ": " + m.path(key) + ": " +
                            lim::out_of_range(*v, limit));
    }
  };
  if (doc->is_null()) {
    return R::failure(file_name + ":1: empty document, expected sensors");
  }
  hal::Calibration c;
  {
    yaml::MappingReader cam = root.required_mapping("camera");
    const auto width = cam.required_int("width");
    const auto height = cam.required_int("height");
    constexpr std::int64_t kIntMax = std::numeric_limits<int>::max();
    c.camera.width = static_cast<int>(std::clamp<std::int64_t>(width, -1, kIntMax));
    c.camera.height = static_cast<int>(std::clamp<std::int64_t>(height, -1, kIntMax));
    c.camera.fx = cam.required_double("fx");
    c.camera.fy = cam.required_double("fy");
    c.camera.cx = cam.required_double("cx");
    c.camera.cy = cam.required_double("cy");
    if (diag.ok()) {
      for (const auto& e : lim::camera_geometry_errors(c.camera, cam.path(""))) {
        const yaml::Node* n = cam.node(e.key);
        diag.errors.push_back((n != nullptr ? n->location.str() : file_name) + ": " +
                              cam.path(e.key) + ": " + e.message);
      }
    }
    const auto dist = cam.optional_doubles("distortion", {0.0, 0.0, 0.0, 0.0}, 4);
    for (std::size_t i = 0; i < 4 && i < dist.size(); ++i) {
      c.camera.distortion[i] = dist[i];
      if (!lim::kDistortion.contains(dist[i])) {
        diag.errors.push_back(cam.node("distortion")->location.str() + ": " +
                              cam.path("distortion") + ": " +
                              lim::out_of_range(dist[i], lim::kDistortion));
      }
    }
    const yaml::Node* tnode = cam.node("T_body_cam");
    const auto t = cam.required_doubles("T_body_cam", 16);
    if (t.size() == 16) {
      std::copy(t.begin(), t.end(), c.camera.T_body_cam.begin());
      if (const char* bad = hal::camera_mount_error(c.camera.T_body_cam)) {
        diag.errors.push_back((tnode != nullptr ? tnode->location.str() : file_name) +
                              ": camera.T_body_cam: " + bad);
      }
    }
    c.camera.pixel_noise = cam.optional_double("pixel_noise", c.camera.pixel_noise);
    c.camera.time_offset_s = cam.optional_double("time_offset_s", 0.0);
    check(cam, "pixel_noise", lim::kPixelNoisePx);
    check(cam, "time_offset_s", lim::kTimeOffsetS);
    if (std::abs(c.camera.time_offset_s) > lim::kPlausibleTimeOffsetS &&
        lim::kTimeOffsetS.contains(c.camera.time_offset_s)) {
      const yaml::Node* n = cam.node("time_offset_s");
      diag.warnings.push_back((n != nullptr ? n->location.str() : file_name) + ": " +
                              cam.path("time_offset_s") + ": " +
                              lim::implausible_time_offset(c.camera.time_offset_s));
    }
    cam.report_unknown_keys();
  }
  {
    yaml::MappingReader w = root.required_mapping("wheels");
    c.wheels.ticks_per_meter_left = w.required_double("ticks_per_meter_left");
    c.wheels.ticks_per_meter_right = w.required_double("ticks_per_meter_right");
    c.wheels.wheel_base = w.required_double("wheel_base");
    c.wheels.distance_noise = w.optional_double("distance_noise", c.wheels.distance_noise);
    c.wheels.scale_error = w.optional_double("scale_error", c.wheels.scale_error);
    check(w, "ticks_per_meter_left", lim::kTicksPerMeter);
    check(w, "ticks_per_meter_right", lim::kTicksPerMeter);
    check(w, "wheel_base", lim::kWheelBaseM);
    check(w, "distance_noise", lim::kFraction);
    check(w, "scale_error", lim::kFraction);
    w.report_unknown_keys();
  }
  {
    yaml::MappingReader g = root.required_mapping("gyro");
    c.gyro.noise_density = g.required_double("noise_density");
    c.gyro.bias_instability = g.optional_double("bias_instability", c.gyro.bias_instability);
    c.gyro.scale_error = g.optional_double("scale_error", c.gyro.scale_error);
    c.gyro.bias_walk = g.optional_double("bias_walk", c.gyro.bias_walk);
    check(g, "noise_density", lim::kNoiseDensity);
    check(g, "bias_instability", lim::kGyroBias);
    check(g, "scale_error", lim::kFraction);
    check(g, "bias_walk", lim::kGyroBias);
    g.report_unknown_keys();
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
