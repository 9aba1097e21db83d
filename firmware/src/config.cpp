#include "cleanslam/firmware/config.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>

#include "cleanslam/firmware/robot_calibration.hpp"
#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/calibration_limits.hpp"
#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/yaml_document.hpp"
#include "parameter_sections.hpp"

namespace cleanslam::firmware {

namespace yaml = readers::yaml;

namespace {

// Typed reading with ranges: errors name the file, line and dotted key.
class Section {
 public:
  Section(yaml::MappingReader reader, yaml::Diagnostics& d) : m_(std::move(reader)), d_(d) {}

  // `why`, when given, follows the range in the message.
  double number(const char* key, double fallback, double lo, double hi, bool lo_open = false,
                const char* why = nullptr) {
    const double v = m_.optional_double(key, fallback);
    if (m_.has(key) && (v < lo || v > hi || (lo_open && v <= lo))) {
      std::ostringstream s;
      s << where(key) << ": " << v << " is out of range " << (lo_open ? "(" : "[") << lo << ", "
        << hi << "]" << (why != nullptr ? ": " : "") << (why != nullptr ? why : "");
      d_.errors.push_back(s.str());
      return fallback;
    }
    return v;
  }
  double number(const char* key, double fallback, hal::calibration_limits::Limit limit) {
    return number(key, fallback, limit.lo, limit.hi, limit.lo_open);
  }
  // A number checked by the caller.
  double value(const char* key, double fallback) { return m_.optional_double(key, fallback); }
  int integer(const char* key, int fallback, std::int64_t lo, std::int64_t hi) {
    const std::int64_t v = m_.optional_int(key, fallback);
    if (m_.has(key) && (v < lo || v > hi)) {
      d_.errors.push_back(where(key) + ": " + std::to_string(v) + " is out of range [" +
                          std::to_string(lo) + ", " + std::to_string(hi) + "]");
      return fallback;
    }
    return static_cast<int>(v);
  }
  std::string text(const char* key, const std::string& fallback) {
    return m_.optional_string(key, fallback);
  }
  bool flag(const char* key, bool fallback) { return m_.optional_bool(key, fallback); }
  template <std::size_t N>
  void numbers(const char* key, std::array<double, N>& out) {
    const auto v = m_.optional_doubles(key, std::vector<double>(out.begin(), out.end()), N);
    if (v.size() == N) {
      std::copy(v.begin(), v.end(), out.begin());
    }
  }
  Section sub(const char* key) { return Section(m_.optional_mapping(key), d_); }
  [[nodiscard]] bool has(const char* key) const { return m_.has(key); }
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

// The shortest map.save_interval_s: saving on every loop iteration would starve the sensors.
constexpr double kMinSaveIntervalS = 0.1;

hal::TimeNs seconds(double s) {
  return static_cast<hal::TimeNs>(std::llround(s * 1e9));
}

void read_calibration(Section c, hal::Calibration& cal) {
  {
    Section cam = c.sub("camera");
    cal.camera.width = cam.integer("width", cal.camera.width, 1, hal::kImageWidth);
    cal.camera.height = cam.integer("height", cal.camera.height, 1, hal::kImageHeight);
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
    cal.camera.pixel_noise = cam.number("pixel_noise", cal.camera.pixel_noise, lim::kPixelNoisePx);
    cal.camera.time_offset_s =
        cam.number("time_offset_s", cal.camera.time_offset_s, lim::kTimeOffsetS);
    if (std::abs(cal.camera.time_offset_s) > lim::kPlausibleTimeOffsetS) {
      cam.warning("time_offset_s", lim::implausible_time_offset(cal.camera.time_offset_s));
    }
    cam.done();
  }
  {
    Section w = c.sub("wheels");
    auto& wh = cal.wheels;
    wh.ticks_per_meter_left =
        w.number("ticks_per_meter_left", wh.ticks_per_meter_left, lim::kTicksPerMeter);
    wh.ticks_per_meter_right =
        w.number("ticks_per_meter_right", wh.ticks_per_meter_right, lim::kTicksPerMeter);
    wh.wheel_base = w.number("wheel_base", wh.wheel_base, lim::kWheelBaseM);
    wh.distance_noise = w.number("distance_noise", wh.distance_noise, lim::kFraction);
    wh.scale_error = w.number("scale_error", wh.scale_error, lim::kFraction);
    w.done();
  }
  {
    Section g = c.sub("gyro");
    cal.gyro.noise_density = g.number("noise_density", cal.gyro.noise_density, lim::kNoiseDensity);
    cal.gyro.bias_instability =
        g.number("bias_instability", cal.gyro.bias_instability, lim::kGyroBias);
    cal.gyro.scale_error = g.number("scale_error", cal.gyro.scale_error, lim::kFraction);
    cal.gyro.bias_walk = g.number("bias_walk", cal.gyro.bias_walk, lim::kGyroBias);
    g.done();
  }
  c.done();
}

template <typename Config>
void read_leaves(Section& s, std::span<const slam_core::Parameter<Config>> table,
                 const std::string& prefix, Config& config) {
  for (const auto& p : table) {
    const std::string name(parameter_sections::leaf_name(p.key, prefix));
    if (name.empty()) {
      continue;
    }
    const double current = slam_core::get_parameter(p, config);
    double v = current;
    switch (slam_core::parameter_type(p)) {
      case slam_core::ParameterType::kBool:
        v = s.flag(name.c_str(), current != 0.0) ? 1.0 : 0.0;
        break;
      case slam_core::ParameterType::kInt:
        v = s.integer(name.c_str(), static_cast<int>(current), static_cast<std::int64_t>(p.lo),
                      static_cast<std::int64_t>(p.hi));
        break;
      case slam_core::ParameterType::kFloat:
      case slam_core::ParameterType::kDouble:
        v = s.number(name.c_str(), current, p.lo, p.hi, p.lo_open);
        break;
    }
    slam_core::set_parameter(p, config, v);
  }
}

// The keys of the parameter tables below `prefix`, nested mappings included.
void read_parameters(Section& s, const std::string& prefix, FirmwareConfig& cfg) {
  read_leaves(s, slam_core::slam_parameters(), prefix, cfg.slam);
  for (const std::string& child : parameter_sections::children(prefix)) {
    Section sub = s.sub(child.c_str());
    read_parameters(sub, prefix + child + ".", cfg);
    sub.done();
  }
}

void write_parameters(std::ostream& s, const std::string& prefix, const std::string& indent,
                      const FirmwareConfig& c) {
  const auto leaves = [&](const auto& table, const auto& config) {
    for (const auto& p : table) {
      const std::string_view name = parameter_sections::leaf_name(p.key, prefix);
      if (!name.empty()) {
        s << indent << name << ": "
          << parameter_sections::value_text(slam_core::parameter_type(p),
                                            slam_core::get_parameter(p, config))
          << "\n";
      }
    }
  };
  leaves(slam_core::slam_parameters(), c.slam);
  for (const std::string& child : parameter_sections::children(prefix)) {
    s << indent << child << ":\n";
    write_parameters(s, prefix + child + ".", indent + "  ", c);
  }
}

void read_all(const yaml::Node& root, yaml::Diagnostics& d, FirmwareConfig& cfg) {
  Section top(yaml::MappingReader(root, "", d), d);
  cfg.calibration_from_dataset = top.flag("calibration_from_dataset", cfg.calibration_from_dataset);
  read_calibration(top.sub("calibration"), cfg.calibration);
  for (const std::string& section : parameter_sections::children("")) {
    Section sec = top.sub(section.c_str());
    read_parameters(sec, section + ".", cfg);
    sec.done();
  }
  {
    Section l = top.sub("loop");
    auto& x = cfg.loop;
    x.frame_rate_hz = l.number("frame_rate_hz", x.frame_rate_hz, 0.1, 30.0);
    x.publish_rate_hz = l.number("publish_rate_hz", x.publish_rate_hz, 1.0, 200.0);
    x.gyro_timeout_ns = seconds(l.number("gyro_timeout_s", 0.1, 0.001, 10.0));
    x.encoder_timeout_ns = seconds(l.number("encoder_timeout_s", 0.25, 0.001, 10.0));
    x.camera_timeout_ns = seconds(l.number("camera_timeout_s", 3.0, 0.01, 60.0));
    x.max_time_skew_ns = seconds(l.number("max_time_skew_s", 1.0, 0.001, 60.0));
    x.max_lead_ns = seconds(l.number("max_lead_s", 0.01, 0.0, 60.0));
    x.max_span_ns = seconds(l.number("max_span_s", 86400.0, 1.0, 3.0e7));
    x.frame_work_budget = l.integer("frame_work_budget", x.frame_work_budget, 1, 1 << 20);
    l.done();
  }
  {
    Section s = top.sub("source");
    auto& x = cfg.source;
    const std::string kind = s.text("kind", "drivers");
    if (kind == "drivers") {
      x.kind = SourceSettings::Kind::kDrivers;
    } else if (kind == "dataset") {
      x.kind = SourceSettings::Kind::kDataset;
    } else if (kind == "log") {
      x.kind = SourceSettings::Kind::kLog;
    } else {
      s.error("kind", "\"" + kind + "\" is not one of drivers, dataset, log");
    }
    x.path = s.text("path", x.path);
    if (x.kind != SourceSettings::Kind::kDrivers && x.path.empty()) {
      s.error("path", "a " + kind + " source needs a path");
    }
    x.realtime = s.flag("realtime", x.realtime);
    x.camera_device = s.text("camera_device", x.camera_device);
    x.can_interface = s.text("can_interface", x.can_interface);
    x.gpio_chip = s.text("gpio_chip", x.gpio_chip);
    x.lift_line = s.integer("lift_line", x.lift_line, -1, 1023);
    s.done();
  }
  {
    Section s = top.sub("sinks");
    auto& x = cfg.sinks;
    x.tum_path = s.text("tum", x.tum_path);
    x.diagnostics_path = s.text("diagnostics", x.diagnostics_path);
    x.can = s.flag("can", x.can);
    x.can_interface = s.text("can_interface", x.can_interface);
    x.rotation.max_file_bytes = static_cast<std::size_t>(
        s.number("max_file_mb", static_cast<double>(x.rotation.max_file_bytes >> 20), 1.0, 1e5) *
        1048576.0);
    x.rotation.max_files = s.integer("max_files", x.rotation.max_files, 1, 1000);
    s.done();
  }
  {
    Section r = top.sub("robot");
    auto& x = cfg.robot;
    slam_core::MapConfig& m = cfg.slam.map;
    using SetDown = slam_core::MapConfig::SetDown;
    const std::string set_down =
        r.text("on_set_down", m.on_set_down == SetDown::kRelocalize ? "relocalize" : "new_map");
    if (set_down == "relocalize") {
      m.on_set_down = SetDown::kRelocalize;
    } else if (set_down == "new_map") {
      m.on_set_down = SetDown::kNewMap;
    } else {
      r.error("on_set_down", "\"" + set_down + "\" is not one of relocalize, new_map");
    }
    m.relocalize_std_m = r.number("relocalize_std_m", m.relocalize_std_m, 0.0, 100.0);
    m.relocalize_std_yaw_deg =
        r.number("relocalize_std_yaw_deg", m.relocalize_std_yaw_deg, 0.0, 180.0);
    x.status_led_line = r.integer("status_led_line", x.status_led_line, -1, 1023);
    x.gyro_ready_line = r.integer("gyro_ready_line", x.gyro_ready_line, -1, 1023);
    x.gyro_ready_max_latency_s =
        r.number("gyro_ready_max_latency_s", x.gyro_ready_max_latency_s, 0.0001, 1.0);
    r.done();
  }
  {
    Section r = top.sub("recorder");
    auto& x = cfg.recorder;
    x.path = r.text("path", x.path);
    x.max_file_bytes = static_cast<std::size_t>(
        r.number("max_file_mb", static_cast<double>(x.max_file_bytes >> 20), 1.0, 1e5) * 1048576.0);
    x.max_files = r.integer("max_files", x.max_files, 1, 1000);
    x.frame_every = r.integer("frame_every", x.frame_every, 0, 1000000);
    x.buffer_bytes = static_cast<std::size_t>(r.integer(
                         "buffer_kb", static_cast<int>(x.buffer_bytes >> 10), 128, 1 << 20))
                     << 10;
    x.write_chunk_bytes =
        static_cast<std::size_t>(
            r.integer("write_chunk_kb", static_cast<int>(x.write_chunk_bytes >> 10), 1, 1 << 20))
        << 10;
    r.done();
  }
  {
    Section m = top.sub("map");
    auto& x = cfg.map;
    x.path = m.text("path", x.path);
    x.save_interval_s =
        m.number("save_interval_s", x.save_interval_s, kMinSaveIntervalS, 86400.0, false,
                 "a save holds the loop while it writes and syncs the map, so at most ten a "
                 "second");
    m.done();
  }
  top.done();
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

std::string fmt(double v) {
  return readers::format_double(v);
}

// A YAML double-quoted scalar that reads back as s: quotes, backslashes and every character YAML
// does not print (controls, C1 controls, line and paragraph separators, the byte order mark) are
// escaped; a raw line break would be folded into a space when read back.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  char buf[16];
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t n = 1;
    std::uint32_t cp = c;
    if (c >= 0xC0 && c < 0xE0 && i + 1 < s.size()) {
      n = 2;
      cp = ((c & 0x1FU) << 6) | (static_cast<unsigned char>(s[i + 1]) & 0x3FU);
    } else if (c >= 0xE0 && c < 0xF0 && i + 2 < s.size()) {
      n = 3;
      cp = ((c & 0x0FU) << 12) | ((static_cast<unsigned char>(s[i + 1]) & 0x3FU) << 6) |
           (static_cast<unsigned char>(s[i + 2]) & 0x3FU);
    } else if (c >= 0xF0 && i + 3 < s.size()) {
      n = 4;  // beyond the characters escaped below
      cp = 0x10000;
    }
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (cp < 0x20 || cp == 0x7F || (cp >= 0x80 && cp < 0xA0)) {
      std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned>(cp));
      out += buf;
    } else if (cp == 0x2028 || cp == 0x2029 || cp == 0xFEFF || cp == 0xFFFE || cp == 0xFFFF) {
      std::snprintf(buf, sizeof buf, "\\u%04X", static_cast<unsigned>(cp));
      out += buf;
    } else {
      out.append(s, i, n);
    }
    i += n;
  }
  return out + "\"";
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
  std::ostringstream s;
  const auto secs = [](hal::TimeNs ns) { return fmt(static_cast<double>(ns) * 1e-9); };
  s << "calibration_from_dataset: " << (c.calibration_from_dataset ? "true" : "false") << "\n";
  s << "calibration:\n";
  std::istringstream cal(readers::sensors_yaml_text(c.calibration));
  for (std::string line; std::getline(cal, line);) {
    s << "  " << line << "\n";
  }
  for (const std::string& section : parameter_sections::children("")) {
    s << section << ":\n";
    write_parameters(s, section + ".", "  ", c);
  }
  const auto& l = c.loop;
  s << "loop:\n"
    << "  frame_rate_hz: " << fmt(l.frame_rate_hz) << "\n"
    << "  publish_rate_hz: " << fmt(l.publish_rate_hz) << "\n"
    << "  gyro_timeout_s: " << secs(l.gyro_timeout_ns) << "\n"
    << "  encoder_timeout_s: " << secs(l.encoder_timeout_ns) << "\n"
    << "  camera_timeout_s: " << secs(l.camera_timeout_ns) << "\n"
    << "  max_time_skew_s: " << secs(l.max_time_skew_ns) << "\n"
    << "  max_lead_s: " << secs(l.max_lead_ns) << "\n"
    << "  max_span_s: " << secs(l.max_span_ns) << "\n"
    << "  frame_work_budget: " << l.frame_work_budget << "\n";
  const auto& so = c.source;
  const char* kind = so.kind == SourceSettings::Kind::kDrivers   ? "drivers"
                     : so.kind == SourceSettings::Kind::kDataset ? "dataset"
                                                                 : "log";
  s << "source:\n"
    << "  kind: " << kind << "\n"
    << "  path: " << quoted(so.path) << "\n"
    << "  realtime: " << (so.realtime ? "true" : "false") << "\n"
    << "  camera_device: " << quoted(so.camera_device) << "\n"
    << "  can_interface: " << quoted(so.can_interface) << "\n"
    << "  gpio_chip: " << quoted(so.gpio_chip) << "\n"
    << "  lift_line: " << so.lift_line << "\n";
  const auto& k = c.sinks;
  s << "sinks:\n"
    << "  tum: " << quoted(k.tum_path) << "\n"
    << "  diagnostics: " << quoted(k.diagnostics_path) << "\n"
    << "  can: " << (k.can ? "true" : "false") << "\n"
    << "  can_interface: " << quoted(k.can_interface) << "\n"
    << "  max_file_mb: " << fmt(static_cast<double>(k.rotation.max_file_bytes) / 1048576.0) << "\n"
    << "  max_files: " << k.rotation.max_files << "\n";
  const auto& r = c.recorder;
  s << "recorder:\n"
    << "  path: " << quoted(r.path) << "\n"
    << "  max_file_mb: " << fmt(static_cast<double>(r.max_file_bytes) / 1048576.0) << "\n"
    << "  max_files: " << r.max_files << "\n"
    << "  frame_every: " << r.frame_every << "\n"
    << "  buffer_kb: " << (r.buffer_bytes >> 10) << "\n"
    << "  write_chunk_kb: " << (r.write_chunk_bytes >> 10) << "\n";
  const auto& b = c.robot;
  const slam_core::MapConfig& m = c.slam.map;
  s << "robot:\n"
    << "  on_set_down: "
    << (m.on_set_down == slam_core::MapConfig::SetDown::kRelocalize ? "relocalize" : "new_map")
    << "\n"
    << "  relocalize_std_m: " << fmt(m.relocalize_std_m) << "\n"
    << "  relocalize_std_yaw_deg: " << fmt(m.relocalize_std_yaw_deg) << "\n"
    << "  status_led_line: " << b.status_led_line << "\n"
    << "  gyro_ready_line: " << b.gyro_ready_line << "\n"
    << "  gyro_ready_max_latency_s: " << fmt(b.gyro_ready_max_latency_s) << "\n";
  s << "map:\n"
    << "  path: " << quoted(c.map.path) << "\n"
    << "  save_interval_s: " << fmt(c.map.save_interval_s) << "\n";
  return s.str();
}

}  // namespace cleanslam::firmware
