#include "cleanslam/sim_hal/sim/waypoint_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cleanslam::sim_hal::sim {
namespace {

// The segment between two waypoints, on the floor, against the box grown by `r` on every side.
bool segment_crosses_footprint(const std::array<double, 2>& a, const std::array<double, 2>& b,
                               const Box& box, double r) {
  const Box grown{box.min - Vec3{r, r, r}, box.max + Vec3{r, r, r}};
  return segment_hits_box(Vec3{a[0], a[1], box.min.z}, Vec3{b[0], b[1], box.min.z}, grown);
}

std::string point_text(const std::array<double, 2>& p) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "(%g, %g)", p[0], p[1]);
  return buf;
}

}  // namespace

std::vector<std::string> waypoint_path_errors(const Scenario& sc) {
  std::vector<std::string> errors;
  const auto& w = sc.path.waypoints;
  const double r = sc.robot.radius;
  if (w.size() < 2) {
    errors.emplace_back("path.waypoints: a waypoints path needs two points at least, got " +
                        std::to_string(w.size()));
    return errors;
  }
  for (std::size_t i = 0; i < w.size(); ++i) {
    const bool inside = w[i][0] >= r && w[i][0] <= sc.world.size.x - r && w[i][1] >= r &&
                        w[i][1] <= sc.world.size.y - r;
    if (!inside) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "path.waypoints[%zu]: %s is outside the world (world.size %g x %g m, less "
                    "robot.radius %g m from its walls)",
                    i, point_text(w[i]).c_str(), sc.world.size.x, sc.world.size.y, r);
      errors.emplace_back(buf);
    }
  }
  if (!errors.empty()) {
    return errors;
  }
  const std::vector<Box> boxes = solid_boxes(sc.world);
  const std::size_t furniture = sc.world.furniture.size();
  for (std::size_t i = 0; i + 1 < w.size(); ++i) {
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      if (!segment_crosses_footprint(w[i], w[i + 1], boxes[k], r)) {
        continue;
      }
      const std::string box = k < furniture ? "world.furniture[" + std::to_string(k) + "]"
                                            : "world.walls[" + std::to_string(k - furniture) + "]";
      char buf[96];
      std::snprintf(buf, sizeof buf, " (robot.radius %g m)", r);
      errors.push_back("path.waypoints[" + std::to_string(i) + "] -> [" + std::to_string(i + 1) +
                       "]: the segment " + point_text(w[i]) + " -> " + point_text(w[i + 1]) +
                       " runs through " + box + buf);
      break;
    }
  }
  return errors;
}

}  // namespace cleanslam::sim_hal::sim
