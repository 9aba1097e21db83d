#include "cleanslam/sim_hal/sim/scenario.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include "cleanslam/readers/yaml_document.hpp"
#include "cleanslam/sim_hal/sim/waypoint_check.hpp"

namespace cleanslam::sim_hal::sim {
namespace {

using readers::yaml::MappingReader;
using readers::yaml::Node;

// Overlays `top` on `base`: mappings merge key by key, anything else replaces.
void overlay(Node& base, const Node& top) {
  if (!base.is_mapping() || !top.is_mapping()) {
    base = top;
    return;
  }
  for (const Node::Entry& e : top.entries) {
    bool found = false;
    for (Node::Entry& b : base.entries) {
      if (b.key == e.key) {
        overlay(b.value, e.value);
        found = true;
        break;
      }
    }
    if (!found) {
      base.entries.push_back(e);
    }
  }
}

readers::Result<Node> load_tree(const std::string& name_or_path, int depth) {
  if (depth > 8) {
    return readers::Result<Node>::failure(name_or_path + ": base scenarios nest too deep");
  }
  const std::string builtin = builtin_scenario_text(name_or_path);
  readers::Result<Node> doc =
      builtin.empty() ? readers::yaml::parse_file(name_or_path)
                      : readers::yaml::parse_string(builtin, "scenarios/" + name_or_path + ".yaml");
  if (!doc.ok()) {
    if (builtin.empty() && !std::filesystem::exists(name_or_path)) {
      std::string names;
      for (const auto& n : builtin_scenario_names()) {
        names += " " + n;
      }
      return readers::Result<Node>::failure(
          name_or_path + ": neither a scenario file nor a built-in scenario (built in:" + names +
          ")");
    }
    return doc;
  }
  Node root = std::move(doc).value();
  if (root.is_null()) {
    root.kind = Node::Kind::kMapping;
  }
  if (!root.is_mapping()) {
    return readers::Result<Node>::failure(root.location.str() + ": a scenario must be a mapping");
  }
  if (const Node* base = root.find("base"); base != nullptr) {
    auto base_name = readers::yaml::as_string(*base, "base");
    if (!base_name.ok()) {
      return readers::Result<Node>::failure(base_name.error());
    }
    auto base_tree = load_tree(*base_name, depth + 1);
    if (!base_tree.ok()) {
      return base_tree;
    }
    Node merged = std::move(base_tree).value();
    overlay(merged, root);
    return merged;
  }
  return root;
}

readers::Status apply_override(Node& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    return readers::Status::failure("--set " + assignment + ": expected key=value");
  }
  const std::string key = assignment.substr(0, eq);
  auto value = readers::yaml::parse_string(assignment.substr(eq + 1), "--set " + key);
  if (!value.ok()) {
    return readers::Status::failure(value.error());
  }
  Node* node = &root;
  std::size_t start = 0;
  while (true) {
    const auto dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? dot : dot - start);
    if (part.empty()) {
      return readers::Status::failure("--set " + key + ": empty key part");
    }
    if (!node->is_mapping()) {
      node->kind = Node::Kind::kMapping;
      node->entries.clear();
    }
    Node* child = nullptr;
    for (Node::Entry& e : node->entries) {
      if (e.key == part) {
        child = &e.value;
      }
    }
    if (child == nullptr) {
      node->entries.push_back(Node::Entry{part, value->location, Node{}});
      child = &node->entries.back().value;
    }
    node = child;
    if (dot == std::string::npos) {
      break;
    }
    start = dot + 1;
  }
  *node = std::move(value).value();
  return readers::Status();
}

Vec3 read_vec3(MappingReader& r, const char* key, Vec3 fallback) {
  const auto v = r.optional_doubles(key, {fallback.x, fallback.y, fallback.z}, 3);
  return v.size() == 3 ? Vec3{v[0], v[1], v[2]} : fallback;
}

int read_int(MappingReader& r, const char* key, int fallback) {
  const auto v = r.optional_int(key, fallback);
  return static_cast<int>(std::clamp<std::int64_t>(v, std::numeric_limits<int>::min(),
                                                   std::numeric_limits<int>::max()));
}

}  // namespace

bool segment_hits_box(Vec3 a, Vec3 b, const Box& box) {
  double s0 = 0.0, s1 = 1.0;
  const double ad[3] = {a.x, a.y, a.z};
  const double dd[3] = {b.x - a.x, b.y - a.y, b.z - a.z};
  const double lo[3] = {box.min.x, box.min.y, box.min.z};
  const double hi[3] = {box.max.x, box.max.y, box.max.z};
  for (int i = 0; i < 3; ++i) {
    if (std::abs(dd[i]) < 1e-15) {
      if (ad[i] < lo[i] || ad[i] > hi[i]) {
        return false;
      }
      continue;
    }
    double t0 = (lo[i] - ad[i]) / dd[i];
    double t1 = (hi[i] - ad[i]) / dd[i];
    if (t0 > t1) {
      std::swap(t0, t1);
    }
    s0 = std::max(s0, t0);
    s1 = std::min(s1, t1);
    if (s0 > s1) {
      return false;
    }
  }
  return true;
}

std::vector<Box> solid_boxes(const Scenario::World& world) {
  std::vector<Box> out;
  for (Box b : world.furniture) {
    b.min = b.min + b.moved_by;
    b.max = b.max + b.moved_by;
    b.moved_by = Vec3{};
    out.push_back(b);
  }
  out.insert(out.end(), world.walls.begin(), world.walls.end());
  return out;
}

readers::Result<Scenario> load_scenario(const std::string& name_or_path,
                                        const std::vector<std::string>& overrides) {
  using R = readers::Result<Scenario>;
  auto tree = load_tree(name_or_path, 0);
  if (!tree.ok()) {
    return R::failure(tree.error());
  }
  Node root = std::move(tree).value();
  for (const std::string& o : overrides) {
    readers::Status s = apply_override(root, o);
    if (!s) {
      return R::failure(s.error());
    }
  }
  readers::yaml::Diagnostics diag;
  MappingReader r(root, "", diag);
  Scenario sc;
  r.optional_string("base", "");
  sc.name = r.optional_string("name", std::filesystem::path(name_or_path).stem().string());
  sc.seed = static_cast<std::uint64_t>(r.optional_int("seed", 1));
  sc.start_time_s = r.optional_double("start_time_s", sc.start_time_s);
  sc.duration_s = r.optional_double("duration_s", sc.duration_s);
  {
    MappingReader w = r.optional_mapping("world");
    sc.world.size = read_vec3(w, "size", sc.world.size);
    if (w.has("seed")) {
      sc.world.seed = static_cast<std::uint64_t>(w.optional_int("seed", 0));
    }
    for (const bool furniture : {true, false}) {
      const std::string key = furniture ? "furniture" : "walls";
      const Node* f = w.node(key);
      if (f == nullptr) {
        continue;
      }
      if (!f->is_sequence()) {
        diag.errors.push_back(f->location.str() + ": world." + key + ": expected a sequence");
        continue;
      }
      for (std::size_t i = 0; i < f->items.size(); ++i) {
        MappingReader b(f->items[i], "world." + key + "[" + std::to_string(i) + "]", diag);
        Box box{read_vec3(b, "min", {}), read_vec3(b, "max", {})};
        b.report_unknown_keys();
        if (!(box.min.x < box.max.x && box.min.y < box.max.y && box.min.z < box.max.z)) {
          diag.errors.push_back("world." + key + "[" + std::to_string(i) +
                                "]: min must be below max on every axis");
        }
        (furniture ? sc.world.furniture : sc.world.walls).push_back(box);
      }
    }
    if (const Node* mv = w.node("moved"); mv != nullptr) {
      if (!mv->is_sequence()) {
        diag.errors.push_back(mv->location.str() + ": world.moved: expected a sequence");
      } else {
        for (std::size_t i = 0; i < mv->items.size(); ++i) {
          const std::string key = "world.moved[" + std::to_string(i) + "]";
          MappingReader m(mv->items[i], key, diag);
          const std::int64_t k = m.required_int("furniture");
          const auto by = m.required_doubles("by", 2);
          m.report_unknown_keys();
          if (k < 0 || k >= static_cast<std::int64_t>(sc.world.furniture.size())) {
            diag.errors.push_back(key + ".furniture: " + std::to_string(k) +
                                  " is not an index of world.furniture (" +
                                  std::to_string(sc.world.furniture.size()) + " boxes)");
          } else if (by.size() == 2) {
            Vec3& d = sc.world.furniture[static_cast<std::size_t>(k)].moved_by;
            d = d + Vec3{by[0], by[1], 0.0};
          }
        }
      }
    }
    w.report_unknown_keys();
  }
  {
    MappingReader m = r.optional_mapping("landmarks");
    auto& l = sc.landmarks;
    l.on_walls = read_int(m, "on_walls", l.on_walls);
    l.on_furniture = read_int(m, "on_furniture", l.on_furniture);
    l.on_interior_walls = read_int(m, "on_interior_walls", l.on_interior_walls);
    l.posts = read_int(m, "posts", l.posts);
    l.min_height = m.optional_double("min_height", l.min_height);
    l.max_height = m.optional_double("max_height", l.max_height);
    l.post_height = m.optional_double("post_height", l.post_height);
    l.post_height_spread = m.optional_double("post_height_spread", l.post_height_spread);
    l.post_margin = m.optional_double("post_margin", l.post_margin);
    m.report_unknown_keys();
  }
  {
    MappingReader m = r.optional_mapping("person");
    auto& p = sc.person;
    p.enabled = m.optional_bool("enabled", p.enabled);
    p.points = read_int(m, "points", p.points);
    p.radius = m.optional_double("radius", p.radius);
    p.height = m.optional_double("height", p.height);
    p.speed = m.optional_double("speed", p.speed);
    p.from = read_vec3(m, "from", p.from);
    p.to = read_vec3(m, "to", p.to);
    m.report_unknown_keys();
  }
  {
    MappingReader m = r.optional_mapping("path");
    auto& p = sc.path;
    p.type = m.optional_string("type", p.type);
    p.speed = m.optional_double("speed", p.speed);
    p.turn_rate = m.optional_double("turn_rate", p.turn_rate);
    p.lane_spacing = m.optional_double("lane_spacing", p.lane_spacing);
    p.margin = m.optional_double("margin", p.margin);
    p.wall_follow = m.optional_bool("wall_follow", p.wall_follow);
    p.repeats = read_int(m, "repeats", p.repeats);
    if (const Node* stops = m.node("stops"); stops != nullptr) {
      if (!stops->is_sequence()) {
        diag.errors.push_back(stops->location.str() + ": path.stops: expected a sequence");
      } else {
        for (std::size_t i = 0; i < stops->items.size(); ++i) {
          MappingReader s(stops->items[i], "path.stops[" + std::to_string(i) + "]", diag);
          p.stops.push_back(StopSpec{s.required_double("at_s"), s.required_double("duration_s")});
          s.report_unknown_keys();
        }
      }
    }
    if (const Node* wp = m.node("waypoints"); wp != nullptr) {
      if (!wp->is_sequence()) {
        diag.errors.push_back(wp->location.str() + ": path.waypoints: expected a sequence");
      } else {
        for (std::size_t i = 0; i < wp->items.size(); ++i) {
          auto xy = readers::yaml::as_doubles(wp->items[i],
                                              "path.waypoints[" + std::to_string(i) + "]", 2);
          if (!xy.ok()) {
            diag.errors.push_back(xy.error());
          } else {
            p.waypoints.push_back({(*xy)[0], (*xy)[1]});
          }
        }
      }
    }
    p.straight_m = m.optional_double("straight_m", p.straight_m);
    p.spin_turns = m.optional_double("spin_turns", p.spin_turns);
    p.settle_s = m.optional_double("settle_s", p.settle_s);
    p.min_speed = m.optional_double("min_speed", p.min_speed);
    p.max_speed = m.optional_double("max_speed", p.max_speed);
    p.min_run = m.optional_double("min_run", p.min_run);
    p.max_run = m.optional_double("max_run", p.max_run);
    p.min_turn_deg = m.optional_double("min_turn_deg", p.min_turn_deg);
    p.max_turn_deg = m.optional_double("max_turn_deg", p.max_turn_deg);
    p.pause_probability = m.optional_double("pause_probability", p.pause_probability);
    p.max_pause_s = m.optional_double("max_pause_s", p.max_pause_s);
    p.goal_bias = m.optional_double("goal_bias", p.goal_bias);
    p.kidnap_at_s = m.optional_double("kidnap_at_s", p.kidnap_at_s);
    p.kidnap_skip_s = m.optional_double("kidnap_skip_s", p.kidnap_skip_s);
    p.lift_duration_s = m.optional_double("lift_duration_s", p.lift_duration_s);
    m.report_unknown_keys();
    if (p.type != "boustrophedon" && p.type != "wander" && p.type != "waypoints" &&
        p.type != "calibration" && p.type != "standstill") {
      diag.errors.push_back(
          "path.type: expected boustrophedon, wander, waypoints, calibration or "
          "standstill, got \"" +
          p.type + "\"");
    }
  }
  {
    MappingReader m = r.optional_mapping("robot");
    sc.robot.wheel_base = m.optional_double("wheel_base", sc.robot.wheel_base);
    sc.robot.ticks_per_meter = m.optional_double("ticks_per_meter", sc.robot.ticks_per_meter);
    sc.robot.initial_ticks = m.optional_int("initial_ticks", sc.robot.initial_ticks);
    sc.robot.radius = m.optional_double("radius", sc.robot.radius);
    m.report_unknown_keys();
  }
  {
    MappingReader m = r.optional_mapping("camera");
    auto& c = sc.camera;
    c.mode = m.optional_string("mode", c.mode);
    c.width = read_int(m, "width", c.width);
    c.height = read_int(m, "height", c.height);
    c.fx = m.optional_double("fx", c.fx);
    c.fy = m.optional_double("fy", c.fy);
    c.cx = m.optional_double("cx", c.cx);
    c.cy = m.optional_double("cy", c.cy);
    const auto d = m.optional_doubles("distortion", {0, 0, 0, 0}, 4);
    for (std::size_t i = 0; i < 4 && i < d.size(); ++i) {
      c.distortion[i] = d[i];
    }
    c.rate_hz = m.optional_double("rate_hz", c.rate_hz);
    c.height_m = m.optional_double("height_m", c.height_m);
    c.forward_m = m.optional_double("forward_m", c.forward_m);
    c.tilt_deg = m.optional_double("tilt_deg", c.tilt_deg);
    c.jitter_s = m.optional_double("jitter_s", c.jitter_s);
    c.pixel_noise = m.optional_double("pixel_noise", c.pixel_noise);
    c.outlier_probability = m.optional_double("outlier_probability", c.outlier_probability);
    c.min_range = m.optional_double("min_range", c.min_range);
    c.max_range = m.optional_double("max_range", c.max_range);
    c.min_facing_cos = m.optional_double("min_facing_cos", c.min_facing_cos);
    c.max_features = read_int(m, "max_features", c.max_features);
    c.image_noise = m.optional_double("image_noise", c.image_noise);
    c.blur = m.optional_double("blur", c.blur);
    c.exposure_walk = m.optional_double("exposure_walk", c.exposure_walk);
    c.exposure_jump_probability =
        m.optional_double("exposure_jump_probability", c.exposure_jump_probability);
    c.image_format = m.optional_string("image_format", c.image_format);
    c.textures = m.optional_string("textures", c.textures);
    c.photo_dir = m.optional_string("photo_dir", c.photo_dir);
    c.exposure_time_s = m.optional_double("exposure_time_s", c.exposure_time_s);
    c.exposure_samples = read_int(m, "exposure_samples", c.exposure_samples);
    c.shot_noise_gain = m.optional_double("shot_noise_gain", c.shot_noise_gain);
    c.vignetting = m.optional_double("vignetting", c.vignetting);
    c.auto_exposure = m.optional_bool("auto_exposure", c.auto_exposure);
    c.auto_exposure_target = m.optional_double("auto_exposure_target", c.auto_exposure_target);
    c.auto_exposure_step_ev = m.optional_double("auto_exposure_step_ev", c.auto_exposure_step_ev);
    m.report_unknown_keys();
    if (c.textures != "procedural" && c.textures != "photos") {
      diag.errors.push_back("camera.textures: expected procedural or photos, got \"" + c.textures +
                            "\"");
    }
    if (c.mode != "features" && c.mode != "images" && c.mode != "both" &&
        c.mode != "checkerboard") {
      diag.errors.push_back("camera.mode: expected features, images, both or checkerboard, got \"" +
                            c.mode + "\"");
    }
    if (c.image_format != "png" && c.image_format != "pgm") {
      diag.errors.push_back("camera.image_format: expected png or pgm, got \"" + c.image_format +
                            "\"");
    }
  }
  {
    MappingReader m = r.optional_mapping("gyro");
    auto& g = sc.gyro;
    g.rate_hz = m.optional_double("rate_hz", g.rate_hz);
    g.noise_density = m.optional_double("noise_density", g.noise_density);
    g.initial_bias = m.optional_double("initial_bias", g.initial_bias);
    g.bias_walk = m.optional_double("bias_walk", g.bias_walk);
    g.scale_error = m.optional_double("scale_error", g.scale_error);
    m.report_unknown_keys();
  }
  {
    MappingReader m = r.optional_mapping("encoders");
    auto& e = sc.encoders;
    e.rate_hz = m.optional_double("rate_hz", e.rate_hz);
    e.scale_error_left = m.optional_double("scale_error_left", e.scale_error_left);
    e.scale_error_right = m.optional_double("scale_error_right", e.scale_error_right);
    e.wheel_base_error = m.optional_double("wheel_base_error", e.wheel_base_error);
    e.distance_noise = m.optional_double("distance_noise", e.distance_noise);
    e.slip_rate_hz = m.optional_double("slip_rate_hz", e.slip_rate_hz);
    e.slip_duration_s = m.optional_double("slip_duration_s", e.slip_duration_s);
    e.slip_fraction = m.optional_double("slip_fraction", e.slip_fraction);
    m.report_unknown_keys();
  }
  {
    MappingReader m = r.optional_mapping("groundtruth");
    sc.groundtruth.rate_hz = m.optional_double("rate_hz", sc.groundtruth.rate_hz);
    m.report_unknown_keys();
  }
  {
    MappingReader m = r.optional_mapping("checkerboard");
    auto& b = sc.checkerboard;
    b.cols = read_int(m, "cols", b.cols);
    b.rows = read_int(m, "rows", b.rows);
    b.square_m = m.optional_double("square_m", b.square_m);
    if (const Node* floor = m.node("on_floor"); floor != nullptr) {
      auto xyz = readers::yaml::as_doubles(*floor, "checkerboard.on_floor", 3);
      if (!xyz.ok()) {
        diag.errors.push_back(xyz.error());
      } else {
        b.on_floor = std::array<double, 3>{(*xyz)[0], (*xyz)[1], (*xyz)[2]};
      }
    }
    m.report_unknown_keys();
  }
  r.report_unknown_keys();
  // In a scenario a misspelt key would silently keep a default: unknown keys are errors.
  for (std::string w : diag.warnings) {
    if (const auto at = w.find(", ignored"); at != std::string::npos) {
      w.erase(at, 9);
    }
    diag.errors.push_back(w);
  }
  auto positive = [&](double v, const char* key) {
    if (!(v > 0.0)) {
      diag.errors.push_back(std::string(key) + ": must be positive");
    }
  };
  positive(sc.camera.rate_hz, "camera.rate_hz");
  positive(sc.gyro.rate_hz, "gyro.rate_hz");
  positive(sc.encoders.rate_hz, "encoders.rate_hz");
  positive(sc.groundtruth.rate_hz, "groundtruth.rate_hz");
  positive(sc.checkerboard.square_m, "checkerboard.square_m");
  if (sc.checkerboard.cols < 2 || sc.checkerboard.rows < 2) {
    diag.errors.push_back("checkerboard.cols, rows: at least 2 inner corners each");
  }
  positive(sc.camera.fx, "camera.fx");
  positive(sc.camera.fy, "camera.fy");
  positive(sc.robot.wheel_base, "robot.wheel_base");
  positive(sc.robot.ticks_per_meter, "robot.ticks_per_meter");
  positive(sc.path.turn_rate, "path.turn_rate");
  positive(sc.path.lane_spacing, "path.lane_spacing");
  positive(sc.world.size.x, "world.size[0]");
  positive(sc.world.size.y, "world.size[1]");
  if (sc.camera.width <= 0 || sc.camera.height <= 0 || sc.camera.width > 4096 ||
      sc.camera.height > 4096) {
    diag.errors.push_back("camera.width/height: out of range");
  }
  if (sc.path.type == "boustrophedon" || sc.path.type == "waypoints" ||
      sc.path.type == "calibration") {
    positive(sc.path.speed, "path.speed");
  }
  if (sc.path.type == "calibration") {
    positive(sc.path.straight_m, "path.straight_m");
    positive(sc.path.spin_turns, "path.spin_turns");
    positive(sc.path.settle_s, "path.settle_s");
  }
  if (sc.path.type == "standstill") {
    positive(sc.duration_s, "duration_s (a standstill needs it)");
  }
  if (sc.path.type == "waypoints") {
    for (std::string& e : waypoint_path_errors(sc)) {
      diag.errors.push_back(std::move(e));
    }
  }
  if (sc.path.type == "wander") {
    positive(sc.duration_s, "duration_s (a wander path needs it)");
    positive(sc.path.min_speed, "path.min_speed");
  }
  if (2.0 * sc.path.margin >= std::min(sc.world.size.x, sc.world.size.y)) {
    diag.errors.push_back("path.margin: leaves no room to drive in world.size");
  }
  // Noises, probabilities and error magnitudes: a negative noise or a probability of 2 is a typo,
  // and a rate of 1e4 Hz writes gigabytes.
  auto within = [&](double v, double lo, double hi, const char* key) {
    if (!(v >= lo && v <= hi)) {
      std::ostringstream m;
      m << key << ": " << v << " is out of range [" << lo << ", " << hi << "]";
      diag.errors.push_back(m.str());
    }
  };
  const auto& cam = sc.camera;
  within(cam.rate_hz, 0.0, 100.0, "camera.rate_hz");
  within(sc.gyro.rate_hz, 0.0, 10000.0, "gyro.rate_hz");
  within(sc.encoders.rate_hz, 0.0, 1000.0, "encoders.rate_hz");
  within(sc.groundtruth.rate_hz, 0.0, 1000.0, "groundtruth.rate_hz");
  within(cam.pixel_noise, 0.0, 100.0, "camera.pixel_noise");
  within(cam.jitter_s, 0.0, 1.0, "camera.jitter_s");
  within(cam.outlier_probability, 0.0, 1.0, "camera.outlier_probability");
  within(cam.min_range, 0.0, cam.max_range, "camera.min_range");
  within(cam.image_noise, 0.0, 255.0, "camera.image_noise");
  within(cam.blur, 0.0, 100.0, "camera.blur");
  within(cam.exposure_walk, 0.0, 1.0, "camera.exposure_walk");
  within(cam.exposure_jump_probability, 0.0, 1.0, "camera.exposure_jump_probability");
  within(cam.exposure_time_s, 0.0, 1.0 / cam.rate_hz, "camera.exposure_time_s");
  within(cam.exposure_samples, 1, 64, "camera.exposure_samples");
  within(cam.shot_noise_gain, 0.0, 10.0, "camera.shot_noise_gain");
  within(cam.vignetting, 0.0, 10.0, "camera.vignetting");
  within(cam.auto_exposure_target, 1.0, 254.0, "camera.auto_exposure_target");
  within(cam.auto_exposure_step_ev, 0.01, 2.0, "camera.auto_exposure_step_ev");
  within(sc.gyro.noise_density, 0.0, 1.0, "gyro.noise_density");
  within(sc.gyro.bias_walk, 0.0, 1.0, "gyro.bias_walk");
  within(sc.gyro.scale_error, -0.5, 0.5, "gyro.scale_error");
  within(sc.encoders.scale_error_left, -0.5, 0.5, "encoders.scale_error_left");
  within(sc.encoders.scale_error_right, -0.5, 0.5, "encoders.scale_error_right");
  within(sc.encoders.wheel_base_error, -0.5, 0.5, "encoders.wheel_base_error");
  within(sc.encoders.distance_noise, 0.0, 1.0, "encoders.distance_noise");
  within(sc.encoders.slip_rate_hz, 0.0, 10.0, "encoders.slip_rate_hz");
  within(sc.encoders.slip_fraction, 0.0, 1.0, "encoders.slip_fraction");
  within(sc.path.pause_probability, 0.0, 1.0, "path.pause_probability");
  // Sizes and counts that would run for hours or fill the memory (a world of 1e6 m, 1e8
  // landmarks, a path repeated 1e6 times), and settings that leave the camera blind.
  within(sc.duration_s, 0.0, 24.0 * 3600.0, "duration_s");
  within(sc.world.size.x, 0.0, 1000.0, "world.size[0]");
  within(sc.world.size.y, 0.0, 1000.0, "world.size[1]");
  within(sc.world.size.z, 0.0, 100.0, "world.size[2]");
  within(sc.landmarks.on_walls, 0.0, 100000.0, "landmarks.on_walls");
  within(sc.landmarks.on_furniture, 0.0, 100000.0, "landmarks.on_furniture");
  within(sc.landmarks.posts, 0.0, 100000.0, "landmarks.posts");
  within(sc.landmarks.on_interior_walls, 0.0, 100000.0, "landmarks.on_interior_walls");
  within(sc.robot.radius, 0.0, 2.0, "robot.radius");
  within(sc.person.points, 0.0, 100000.0, "person.points");
  within(sc.landmarks.min_height, 0.0, sc.landmarks.max_height, "landmarks.min_height");
  within(sc.path.repeats, 1.0, 1000.0, "path.repeats");
  within(sc.path.speed, 0.0, 5.0, "path.speed");
  within(sc.path.max_speed, sc.path.min_speed, 5.0, "path.max_speed");
  within(cam.max_features, 0.0, 100000.0, "camera.max_features");
  within(cam.tilt_deg, -90.0, 90.0, "camera.tilt_deg");
  if (!diag.ok()) {
    return R::failure(diag.error_text());
  }
  return sc;
}

}  // namespace cleanslam::sim_hal::sim
