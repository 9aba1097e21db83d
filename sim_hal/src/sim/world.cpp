#include "cleanslam/sim_hal/sim/world.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

namespace cleanslam::sim_hal::sim {
namespace {

bool inside(const Box& b, Vec3 p, double eps) {
  return p.x > b.min.x - eps && p.x < b.max.x + eps && p.y > b.min.y - eps && p.y < b.max.y + eps &&
         p.z > b.min.z - eps && p.z < b.max.z + eps;
}

// True when one of `boxes` blocks the segment from a to b (b's own surface excluded).
bool blocked(const std::vector<Box>& boxes, Vec3 a, Vec3 b) {
  const Vec3 d = b - a;
  const double len = norm(d);
  if (len < 0.02) {
    return false;
  }
  const Vec3 end = a + ((len - 0.01) / len) * d;  // stop short of b's own surface
  for (const Box& box : boxes) {
    if (segment_hits_box(a, end, box)) {
      return true;
    }
  }
  return false;
}

bool buried(const std::vector<Box>& boxes, Vec3 p) {
  for (const Box& b : boxes) {
    if (inside(b, p, 0.0)) {
      return true;
    }
  }
  return false;
}

bool in_world(Vec3 size, Vec3 p) {
  return p.x > 0.0 && p.y > 0.0 && p.x < size.x && p.y < size.y;
}

// A point on the vertical faces of the interior walls, drawn by face area (heights within
// [lo, hi]); none when no face reaches into that band.
std::optional<Landmark> on_interior_wall(const std::vector<Box>& walls, double lo, double hi,
                                         Random& rng) {
  struct Face {
    const Box* box;
    int side;  // 0: -x, 1: +x, 2: -y, 3: +y
    double area;
  };
  std::vector<Face> faces;
  double total = 0.0;
  for (const Box& b : walls) {
    const double h = std::max(0.0, std::min(hi, b.max.z) - std::max(lo, b.min.z));
    const double dx = b.max.x - b.min.x, dy = b.max.y - b.min.y;
    for (int side = 0; side < 4; ++side) {
      faces.push_back(Face{&b, side, (side < 2 ? dy : dx) * h});
      total += faces.back().area;
    }
  }
  if (!(total > 0.0)) {
    return std::nullopt;
  }
  double pick = rng.uniform(0.0, total);
  const Face* f = &faces.back();
  for (const Face& face : faces) {
    if (pick < face.area) {
      f = &face;
      break;
    }
    pick -= face.area;
  }
  const Box& b = *f->box;
  const double u = rng.uniform(0.0, 1.0);
  const double z = rng.uniform(std::max(lo, b.min.z), std::min(hi, b.max.z));
  Landmark l;
  switch (f->side) {
    case 0:
      l.position = {b.min.x, b.min.y + u * (b.max.y - b.min.y), z};
      l.normal = {-1, 0, 0};
      break;
    case 1:
      l.position = {b.max.x, b.min.y + u * (b.max.y - b.min.y), z};
      l.normal = {1, 0, 0};
      break;
    case 2:
      l.position = {b.min.x + u * (b.max.x - b.min.x), b.min.y, z};
      l.normal = {0, -1, 0};
      break;
    default:
      l.position = {b.min.x + u * (b.max.x - b.min.x), b.max.y, z};
      l.normal = {0, 1, 0};
      break;
  }
  return l;
}

}  // namespace

World::World(const Scenario& sc, Random& rng) : person_(sc.person) {
  const Vec3 size = sc.world.size;
  const auto& lm = sc.landmarks;
  // Landmarks are placed with the furniture where the scenario lists it; moved_by comes after.
  const std::vector<Box>& furniture = sc.world.furniture;
  const std::vector<Box>& walls = sc.world.walls;
  boxes_ = furniture;
  boxes_.insert(boxes_.end(), walls.begin(), walls.end());
  std::vector<int> on_box;  // per landmark: the furniture box it lies on, or -1
  std::int64_t next_id = 0;
  const Vec3 centre{0.5 * size.x, 0.5 * size.y, 0.5};
  const double perimeter = 2.0 * (size.x + size.y);
  int placed = 0, attempts = 0;
  while (placed < lm.on_walls && attempts++ < 100 * lm.on_walls + 100) {
    double s = rng.uniform(0.0, perimeter);
    const double z = rng.uniform(lm.min_height, std::min(lm.max_height, size.z));
    Landmark l;
    if (s < size.x) {
      l.position = {s, 0.0, z};
      l.normal = {0, 1, 0};
    } else if ((s -= size.x) < size.y) {
      l.position = {size.x, s, z};
      l.normal = {-1, 0, 0};
    } else if ((s -= size.y) < size.x) {
      l.position = {size.x - s, size.y, z};
      l.normal = {0, -1, 0};
    } else {
      s -= size.x;
      l.position = {0.0, size.y - s, z};
      l.normal = {1, 0, 0};
    }
    // A wall point hidden behind furniture is never seen, nor one inside an interior wall that
    // meets this wall: place another.
    if (blocked(furniture, centre, l.position) || buried(walls, l.position + 0.05 * l.normal)) {
      continue;
    }
    l.id = next_id++;
    landmarks_.push_back(l);
    on_box.push_back(-1);
    ++placed;
  }
  // Furniture: vertical faces that do not touch a wall, and the top.
  if (!furniture.empty()) {
    placed = 0;
    attempts = 0;
    while (placed < lm.on_furniture && attempts++ < 100 * lm.on_furniture + 100) {
      const std::size_t k = rng.below(furniture.size());
      const Box& b = furniture[k];
      const int face = static_cast<int>(rng.below(5));
      Landmark l;
      const double u = rng.uniform(0.0, 1.0), v = rng.uniform(0.0, 1.0);
      const Vec3 d = b.max - b.min;
      switch (face) {
        case 0:
          l.position = {b.min.x, b.min.y + u * d.y, b.min.z + v * d.z};
          l.normal = {-1, 0, 0};
          break;
        case 1:
          l.position = {b.max.x, b.min.y + u * d.y, b.min.z + v * d.z};
          l.normal = {1, 0, 0};
          break;
        case 2:
          l.position = {b.min.x + u * d.x, b.min.y, b.min.z + v * d.z};
          l.normal = {0, -1, 0};
          break;
        case 3:
          l.position = {b.min.x + u * d.x, b.max.y, b.min.z + v * d.z};
          l.normal = {0, 1, 0};
          break;
        default:
          l.position = {b.min.x + u * d.x, b.min.y + v * d.y, b.max.z};
          l.normal = {0, 0, 1};
          break;
      }
      const Vec3 out = l.position + 0.05 * l.normal;
      if (!in_world(size, out) || buried(boxes_, out)) {
        continue;
      }
      l.id = next_id++;
      landmarks_.push_back(l);
      on_box.push_back(static_cast<int>(k));
      ++placed;
    }
  }
  for (int i = 0; i < lm.posts; ++i) {
    Landmark l;
    l.position = {rng.uniform(lm.post_margin, size.x - lm.post_margin),
                  rng.uniform(lm.post_margin, size.y - lm.post_margin),
                  lm.post_height + rng.uniform(-lm.post_height_spread, lm.post_height_spread)};
    l.id = next_id++;
    landmarks_.push_back(l);
    on_box.push_back(-1);
  }
  // Interior walls, both faces and the door jambs; not where a wall or a box covers the face.
  if (!walls.empty()) {
    placed = 0;
    attempts = 0;
    const double hi = std::min(lm.max_height, size.z);
    while (placed < lm.on_interior_walls && attempts++ < 100 * lm.on_interior_walls + 100) {
      const auto drawn = on_interior_wall(walls, lm.min_height, hi, rng);
      if (!drawn) {
        break;
      }
      Landmark l = *drawn;
      const Vec3 out = l.position + 0.05 * l.normal;
      if (!in_world(size, out) || buried(boxes_, out)) {
        continue;
      }
      l.id = next_id++;
      landmarks_.push_back(l);
      on_box.push_back(-1);
      ++placed;
    }
  }
  // The objects moved since the landmarks were placed take theirs along.
  for (std::size_t i = 0; i < landmarks_.size(); ++i) {
    if (on_box[i] >= 0) {
      landmarks_[i].position =
          landmarks_[i].position + furniture[static_cast<std::size_t>(on_box[i])].moved_by;
    }
  }
  boxes_ = solid_boxes(sc.world);
}

std::vector<Landmark> World::person_points(double t) const {
  std::vector<Landmark> out;
  if (!person_.enabled || person_.points <= 0) {
    return out;
  }
  // Walks from `from` to `to` and back, forever.
  const Vec3 d = person_.to - person_.from;
  const double len = std::max(1e-6, std::hypot(d.x, d.y));
  double s = std::fmod(t * person_.speed, 2.0 * len);
  if (s > len) {
    s = 2.0 * len - s;
  }
  const Vec3 c = person_.from + (s / len) * d;
  for (int i = 0; i < person_.points; ++i) {
    // Points spread over the body in a fixed pattern (golden angle around, even in height).
    const double a = static_cast<double>(i) * 2.399963229728653;
    const double h = person_.height * (static_cast<double>(i) + 0.5) / person_.points;
    Landmark l;
    l.id = kPersonTrackBase + i;
    l.normal = {std::cos(a), std::sin(a), 0.0};
    l.position = {c.x + person_.radius * std::cos(a), c.y + person_.radius * std::sin(a), h};
    out.push_back(l);
  }
  return out;
}

bool World::occluded(Vec3 a, Vec3 b) const {
  return blocked(boxes_, a, b);
}

}  // namespace cleanslam::sim_hal::sim
