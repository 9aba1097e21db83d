#include "cleanslam/sim_hal/sim/scenario.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include "cleanslam/readers/parameter_yaml.hpp"
#include "cleanslam/readers/yaml_document.hpp"
#include "cleanslam/sim_hal/sim/scenario_parameters.hpp"
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

// world.seed, world.furniture, world.walls and world.moved.
void read_world_lists(MappingReader& w, Scenario& sc, readers::yaml::Diagnostics& diag) {
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
      return;
    }
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

// path.stops and path.waypoints.
void read_path_lists(MappingReader& m, Scenario::Path& p, readers::yaml::Diagnostics& diag) {
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
        auto xy =
            readers::yaml::as_doubles(wp->items[i], "path.waypoints[" + std::to_string(i) + "]", 2);
        if (!xy.ok()) {
          diag.errors.push_back(xy.error());
        } else {
          p.waypoints.push_back({(*xy)[0], (*xy)[1]});
        }
      }
    }
  }
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
  sc.name = std::filesystem::path(name_or_path).stem().string();
  const auto table = scenario_parameters();
  readers::read_parameters(r, table, "", sc, diag);
  std::vector<std::string> sections;
  readers::parameter_children(table, "", sections);
  for (const std::string& section : sections) {
    MappingReader m = r.optional_mapping(section);
    readers::read_parameters(m, table, section + ".", sc, diag);
    if (section == "world") {
      read_world_lists(m, sc, diag);
    } else if (section == "path") {
      read_path_lists(m, sc.path, diag);
    } else if (section == "checkerboard") {
      if (const Node* floor = m.node("on_floor"); floor != nullptr) {
        auto xyz = readers::yaml::as_doubles(*floor, "checkerboard.on_floor", 3);
        if (!xyz.ok()) {
          diag.errors.push_back(xyz.error());
        } else {
          sc.checkerboard.on_floor = std::array<double, 3>{(*xyz)[0], (*xyz)[1], (*xyz)[2]};
        }
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
  // What the table's ranges cannot say: keys that depend on each other or on the path's type.
  auto positive = [&](double v, const char* key) {
    if (!(v > 0.0)) {
      diag.errors.push_back(std::string(key) + ": must be positive");
    }
  };
  auto within = [&](double v, double lo, double hi, const char* key) {
    if (!(v >= lo && v <= hi)) {
      std::ostringstream m;
      m << key << ": " << v << " is out of range [" << lo << ", " << hi << "]";
      diag.errors.push_back(m.str());
    }
  };
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
  const auto& cam = sc.camera;
  within(cam.min_range, 0.0, cam.max_range, "camera.min_range");
  within(cam.exposure_time_s, 0.0, 1.0 / cam.rate_hz, "camera.exposure_time_s");
  within(sc.world.size.z, 0.0, 100.0, "world.size[2]");
  within(sc.landmarks.min_height, 0.0, sc.landmarks.max_height, "landmarks.min_height");
  within(sc.path.max_speed, sc.path.min_speed, 5.0, "path.max_speed");
  if (!diag.ok()) {
    return R::failure(diag.error_text());
  }
  return sc;
}

}  // namespace cleanslam::sim_hal::sim
