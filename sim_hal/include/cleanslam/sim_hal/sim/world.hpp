#pragma once

#include <cstdint>
#include <vector>

#include "cleanslam/sim_hal/sim/random.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/sim_math.hpp"

// The simulated room (or home): walls, interior walls, furniture boxes, 3-D point landmarks (on
// walls, on furniture faces, on interior walls, free-standing posts) and an optional walking
// person whose points move (outliers for a static map). Track ids: static landmarks 0.., the
// person's points from kPersonTrackBase.
namespace cleanslam::sim_hal::sim {

inline constexpr std::int64_t kPersonTrackBase = 1'000'000;

struct Landmark {
  std::int64_t id = 0;
  Vec3 position;
  Vec3 normal;  // outward normal of the surface it lies on; zero: visible from every side
};

class World {
 public:
  World(const Scenario& scenario, Random& rng);

  [[nodiscard]] const std::vector<Landmark>& landmarks() const { return landmarks_; }
  // The person's points at path time t (empty when there is no person).
  [[nodiscard]] std::vector<Landmark> person_points(double t) const;
  // True when a furniture box or an interior wall blocks the segment from a to b (b's own
  // surface excluded).
  [[nodiscard]] bool occluded(Vec3 a, Vec3 b) const;
  // The furniture at its place (moved_by applied), then the interior walls.
  [[nodiscard]] const std::vector<Box>& boxes() const { return boxes_; }

 private:
  std::vector<Box> boxes_;
  std::vector<Landmark> landmarks_;
  Scenario::Person person_;
};

}  // namespace cleanslam::sim_hal::sim
