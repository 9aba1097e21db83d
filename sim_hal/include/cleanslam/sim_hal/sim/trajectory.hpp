#pragma once

#include <utility>
#include <vector>

#include "cleanslam/sim_hal/sim/random.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/sim_math.hpp"

// The robot's true motion: a sequence of primitives of constant forward speed v and yaw rate w
// (straight runs, turns in place, arcs, stops) and lifts (carried through the air to another
// pose), integrated exactly. Time is path time, 0 at the start.
namespace cleanslam::sim_hal::sim {

struct PlanarPose {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;  // unwrapped
};

struct Primitive {
  double duration = 0.0;
  double v = 0.0;
  double w = 0.0;
  bool lift = false;
  PlanarPose lift_to;  // lift only
};

struct TrueState {
  Vec3 position;        // body origin (wheel-axis centre on the floor); z > 0 while lifted
  double yaw = 0.0;     // unwrapped
  double left_m = 0.0;  // distance rolled by each wheel (true wheel base)
  double right_m = 0.0;
  bool lifted = false;
};

// Pose of `p` after driving at (v, w) for `t` seconds.
PlanarPose integrate(const PlanarPose& p, double v, double w, double t);

class Trajectory {
 public:
  Trajectory() = default;
  Trajectory(const std::vector<Primitive>& primitives, const PlanarPose& start, double wheel_base);

  [[nodiscard]] TrueState at(double t) const;
  [[nodiscard]] double duration() const { return duration_; }
  // Distance travelled on the floor (lifts excluded).
  [[nodiscard]] double length() const { return length_; }
  // Path times at which lifts start and end.
  [[nodiscard]] std::vector<std::pair<double, double>> lift_intervals() const;
  // Body pose in the world.
  [[nodiscard]] static Pose3 body_pose(const TrueState& s);

 private:
  struct Segment {
    double t0 = 0.0;
    Primitive p;
    PlanarPose start;
    double left0 = 0.0;
    double right0 = 0.0;
  };
  std::vector<Segment> segments_;
  double wheel_base_ = 0.235;
  double duration_ = 0.0;
  double length_ = 0.0;
};

// Primitives of the scenario's path (boustrophedon, wander or waypoints), with its stops and
// kidnapping, and the start pose.
struct PathPlan {
  std::vector<Primitive> primitives;
  PlanarPose start;
};
PathPlan plan_path(const Scenario& scenario, Random& rng);

}  // namespace cleanslam::sim_hal::sim
