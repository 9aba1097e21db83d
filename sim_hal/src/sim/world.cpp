#include "cleanslam/sim_hal/sim/world.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace cleanslam::sim_hal::sim {
namespace {

bool inside(const Box& b, Vec3 p, double eps) {
  return p.x > b.min.x - eps && p.x < b.max.x + eps && p.y > b.min.y - eps && p.y < b.max.y + eps &&
         p.z > b.min.z - eps && p.z < b.max.z + eps;
}

// Slab test of the segment a + s (b - a), s in [0, 1], against a box.
bool segment_hits_box(Vec3 a, Vec3 b, const Box& box) {
  double s0 = 0.0, s1 = 1.0;
  const double ad[3] = {a.x, a.y, a.z};
  const double dd[3] = {b.x - a.x, b.y - a.y, b.z - a.z};
  const double lo[3] = {box.min.x, box.min.y, box.min.z};
  const double hi[3] = {box.max.x, box.max.y, box.max.z};
  for (int i = 0; i < 3; ++i) {
    if (std::abs(dd[i]) < 1e-15) {
      if (ad[i] < lo[i] || ad[i] > hi[i]) return false;
      continue;
    }
    double t0 = (lo[i] - ad[i]) / dd[i];
    double t1 = (hi[i] - ad[i]) / dd[i];
    if (t0 > t1) std::swap(t0, t1);
    s0 = std::max(s0, t0);
    s1 = std::min(s1, t1);
    if (s0 > s1) return false;
  }
  return true;
}

}  // namespace

World::World(const Scenario& sc, Random& rng) : boxes_(sc.world.furniture), person_(sc.person) {
  const Vec3 size = sc.world.size;
  const auto& lm = sc.landmarks;
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
    // A wall point hidden behind furniture is never seen: place another.
    if (occluded(centre, l.position)) continue;
    l.id = next_id++;
    landmarks_.push_back(l);
    ++placed;
  }
  // Furniture: vertical faces that do not touch a wall, and the top.
  if (!boxes_.empty()) {
    placed = 0;
    attempts = 0;
    while (placed < lm.on_furniture && attempts++ < 100 * lm.on_furniture + 100) {
      const Box& b = boxes_[rng.below(boxes_.size())];
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
      if (out.x <= 0.0 || out.y <= 0.0 || out.x >= size.x || out.y >= size.y) continue;
      bool buried = false;
      for (const Box& other : boxes_) buried = buried || inside(other, out, 0.0);
      if (buried) continue;
      l.id = next_id++;
      landmarks_.push_back(l);
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
  }
}

std::vector<Landmark> World::person_points(double t) const {
  std::vector<Landmark> out;
  if (!person_.enabled || person_.points <= 0) return out;
  // Walks from `from` to `to` and back, forever.
  const Vec3 d = person_.to - person_.from;
  const double len = std::max(1e-6, std::hypot(d.x, d.y));
  double s = std::fmod(t * person_.speed, 2.0 * len);
  if (s > len) s = 2.0 * len - s;
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
  const Vec3 d = b - a;
  const double len = norm(d);
  if (len < 0.02) return false;
  const Vec3 end = a + ((len - 0.01) / len) * d;  // stop short of b's own surface
  for (const Box& box : boxes_) {
    if (segment_hits_box(a, end, box)) return true;
  }
  return false;
}

}  // namespace cleanslam::sim_hal::sim
