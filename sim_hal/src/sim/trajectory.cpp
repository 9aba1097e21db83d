#include "cleanslam/sim_hal/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace cleanslam::sim_hal::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kLiftHeight = 0.15;

Primitive motion(double duration, double v, double w) {
  Primitive p;
  p.duration = duration;
  p.v = v;
  p.w = w;
  return p;
}

// Appends primitives that drive `plan` from `pose` to (x, y) as a turn in place then a straight
// run; updates `pose`.
void drive_to(std::vector<Primitive>& out, PlanarPose& pose, double x, double y, double speed,
              double turn_rate) {
  const double dx = x - pose.x;
  const double dy = y - pose.y;
  const double dist = std::hypot(dx, dy);
  if (dist < 1e-9) {
    return;
  }
  const double turn = wrap_angle(std::atan2(dy, dx) - pose.yaw);
  if (std::abs(turn) > 1e-9) {
    out.push_back(motion(std::abs(turn) / turn_rate, 0.0, std::copysign(turn_rate, turn)));
    pose.yaw += turn;
  }
  out.push_back(motion(dist / speed, speed, 0.0));
  pose.x = x;
  pose.y = y;
}

std::vector<Primitive> boustrophedon(const Scenario& sc, PlanarPose& start) {
  const auto& p = sc.path;
  const double x0 = p.margin, y0 = p.margin;
  const double x1 = sc.world.size.x - p.margin, y1 = sc.world.size.y - p.margin;
  start = PlanarPose{x0, y0, 0.0};
  PlanarPose pose = start;
  std::vector<Primitive> out;
  for (int rep = 0; rep < std::max(1, p.repeats); ++rep) {
    if (p.wall_follow) {
      // One lap along the walls, counter-clockwise, at the margin.
      drive_to(out, pose, x0, y0, p.speed, p.turn_rate);
      drive_to(out, pose, x1, y0, p.speed, p.turn_rate);
      drive_to(out, pose, x1, y1, p.speed, p.turn_rate);
      drive_to(out, pose, x0, y1, p.speed, p.turn_rate);
      drive_to(out, pose, x0, y0, p.speed, p.turn_rate);
    }
    // Seed-drill lanes along x, stepping by lane_spacing in y, 90 degree turns at the ends.
    const int lanes = static_cast<int>(std::floor((y1 - y0) / p.lane_spacing + 1e-9)) + 1;
    const bool forward_first = rep % 2 == 0;
    for (int k = 0; k < lanes; ++k) {
      const int lane = forward_first ? k : lanes - 1 - k;
      const double y = y0 + lane * p.lane_spacing;
      const bool east = (k % 2 == 0);
      if (k == 0) {
        drive_to(out, pose, east ? x0 : x1, y, p.speed, p.turn_rate);
      }
      if (k > 0) {
        drive_to(out, pose, pose.x, y, p.speed, p.turn_rate);
      }
      drive_to(out, pose, east ? x1 : x0, y, p.speed, p.turn_rate);
    }
  }
  return out;
}

// From the first waypoint (the dock), facing the second, through the others in turn.
std::vector<Primitive> waypoints(const Scenario& sc, PlanarPose& start) {
  const auto& p = sc.path;
  std::vector<Primitive> out;
  if (p.waypoints.empty()) {
    return out;
  }
  const auto& w0 = p.waypoints.front();
  start = PlanarPose{w0[0], w0[1], 0.0};
  for (const auto& w : p.waypoints) {
    if (std::hypot(w[0] - w0[0], w[1] - w0[1]) > 1e-9) {
      start.yaw = std::atan2(w[1] - w0[1], w[0] - w0[0]);
      break;
    }
  }
  PlanarPose pose = start;
  for (const auto& w : p.waypoints) {
    drive_to(out, pose, w[0], w[1], p.speed, p.turn_rate);
  }
  return out;
}

// The wheels' calibration drive (tools/calibrate wheels): still, straight along +x from the
// arena's corner at the margin, still, full turns counter-clockwise, still, as many clockwise,
// still.
std::vector<Primitive> calibration_drive(const Scenario& sc, PlanarPose& start) {
  const auto& p = sc.path;
  start = PlanarPose{p.margin, p.margin, 0.0};
  const double spin_s = p.spin_turns * 2.0 * kPi / p.turn_rate;
  return {motion(p.settle_s, 0.0, 0.0), motion(p.straight_m / p.speed, p.speed, 0.0),
          motion(p.settle_s, 0.0, 0.0), motion(spin_s, 0.0, p.turn_rate),
          motion(p.settle_s, 0.0, 0.0), motion(spin_s, 0.0, -p.turn_rate),
          motion(p.settle_s, 0.0, 0.0)};
}

// Distance from (x, y) along heading `yaw` to the border of the rectangle [lo, hi].
double distance_to_border(double x, double y, double yaw, double lox, double loy, double hix,
                          double hiy) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  double d = 1e9;
  if (c > 1e-9) {
    d = std::min(d, (hix - x) / c);
  }
  if (c < -1e-9) {
    d = std::min(d, (lox - x) / c);
  }
  if (s > 1e-9) {
    d = std::min(d, (hiy - y) / s);
  }
  if (s < -1e-9) {
    d = std::min(d, (loy - y) / s);
  }
  return std::max(0.0, d);
}

std::vector<Primitive> wander(const Scenario& sc, Random& rng, PlanarPose& start) {
  const auto& p = sc.path;
  const double lox = p.margin, loy = p.margin;
  const double hix = sc.world.size.x - p.margin, hiy = sc.world.size.y - p.margin;
  start = PlanarPose{rng.uniform(lox, hix), rng.uniform(loy, hiy), rng.uniform(-kPi, kPi)};
  PlanarPose pose = start;
  std::vector<Primitive> out;
  double t = 0.0;
  int guard = 0;
  // Random goals across the arena keep the wandering from staying in one corner.
  double goal_x = rng.uniform(lox, hix), goal_y = rng.uniform(loy, hiy);
  while (t < sc.duration_s && ++guard < 1'000'000) {
    if (std::hypot(goal_x - pose.x, goal_y - pose.y) < 1.0) {
      goal_x = rng.uniform(lox, hix);
      goal_y = rng.uniform(loy, hiy);
    }
    // Turn (towards the goal, roughly, or at random), then run as far as the wanted length or the
    // border allows.
    double turn = rng.uniform(p.min_turn_deg, p.max_turn_deg) * kPi / 180.0;
    if (rng.chance(0.5)) {
      turn = -turn;
    }
    if (rng.chance(p.goal_bias)) {
      const double to_goal = std::atan2(goal_y - pose.y, goal_x - pose.x);
      turn = wrap_angle(to_goal + rng.gaussian(0.5) - pose.yaw);
    }
    double heading = pose.yaw + turn;
    double want = rng.uniform(p.min_run, p.max_run);
    if (distance_to_border(pose.x, pose.y, heading, lox, loy, hix, hiy) < p.min_run) {
      // Head for the middle of the arena instead.
      const double cx = 0.5 * (lox + hix) + rng.uniform(-1.0, 1.0);
      const double cy = 0.5 * (loy + hiy) + rng.uniform(-1.0, 1.0);
      turn = wrap_angle(std::atan2(cy - pose.y, cx - pose.x) - pose.yaw);
      heading = pose.yaw + turn;
    }
    const double run =
        std::min(want, distance_to_border(pose.x, pose.y, heading, lox, loy, hix, hiy));
    if (std::abs(turn) > 1e-9) {
      const double d = std::abs(turn) / p.turn_rate;
      out.push_back(motion(d, 0.0, std::copysign(p.turn_rate, turn)));
      t += d;
      pose.yaw = heading;
    }
    if (run > 1e-3) {
      const double v = rng.uniform(p.min_speed, std::max(p.min_speed, p.max_speed));
      out.push_back(motion(run / v, v, 0.0));
      t += run / v;
      pose = integrate(pose, v, 0.0, run / v);
    }
    if (p.pause_probability > 0.0 && rng.chance(p.pause_probability)) {
      const double d = rng.uniform(0.0, p.max_pause_s);
      out.push_back(motion(d, 0.0, 0.0));
      t += d;
    }
  }
  return out;
}

// Splits the primitive that contains path time `t` so that a primitive starts exactly at `t`;
// returns its index (primitives.size() when `t` is at or after the end).
std::size_t split_at(std::vector<Primitive>& prims, double t) {
  double t0 = 0.0;
  for (std::size_t i = 0; i < prims.size(); ++i) {
    const double t1 = t0 + prims[i].duration;
    if (t <= t0 + 1e-12) {
      return i;
    }
    if (t < t1 - 1e-12) {
      Primitive first = prims[i];
      Primitive second = prims[i];
      first.duration = t - t0;
      second.duration = t1 - t;
      prims[i] = first;
      prims.insert(prims.begin() + static_cast<std::ptrdiff_t>(i) + 1, second);
      return i + 1;
    }
    t0 = t1;
  }
  return prims.size();
}

PlanarPose pose_at(const std::vector<Primitive>& prims, const PlanarPose& start, double t) {
  PlanarPose p = start;
  double t0 = 0.0;
  for (const Primitive& q : prims) {
    const double d = std::min(q.duration, t - t0);
    if (d <= 0.0) {
      break;
    }
    p = q.lift ? q.lift_to : integrate(p, q.v, q.w, d);
    t0 += q.duration;
  }
  return p;
}

}  // namespace

PlanarPose integrate(const PlanarPose& p, double v, double w, double t) {
  if (std::abs(w) < 1e-12) {
    return PlanarPose{p.x + v * t * std::cos(p.yaw), p.y + v * t * std::sin(p.yaw), p.yaw};
  }
  const double yaw1 = p.yaw + w * t;
  return PlanarPose{p.x + v / w * (std::sin(yaw1) - std::sin(p.yaw)),
                    p.y - v / w * (std::cos(yaw1) - std::cos(p.yaw)), yaw1};
}

Trajectory::Trajectory(const std::vector<Primitive>& primitives, const PlanarPose& start,
                       double wheel_base)
    : wheel_base_(wheel_base) {
  PlanarPose pose = start;
  double t = 0.0, left = 0.0, right = 0.0;
  for (const Primitive& p : primitives) {
    if (p.duration <= 0.0) {
      continue;
    }
    segments_.push_back(Segment{t, p, pose, left, right});
    if (p.lift) {
      pose = p.lift_to;
    } else {
      pose = integrate(pose, p.v, p.w, p.duration);
      left += (p.v - 0.5 * p.w * wheel_base_) * p.duration;
      right += (p.v + 0.5 * p.w * wheel_base_) * p.duration;
      length_ += std::abs(p.v) * p.duration;
    }
    t += p.duration;
  }
  duration_ = t;
}

TrueState Trajectory::at(double t) const {
  TrueState s;
  if (segments_.empty()) {
    return s;
  }
  t = std::clamp(t, 0.0, duration_);
  auto it = std::upper_bound(segments_.begin(), segments_.end(), t,
                             [](double v, const Segment& seg) { return v < seg.t0; });
  const Segment& seg = it == segments_.begin() ? segments_.front() : *(it - 1);
  const double tau = std::min(t - seg.t0, seg.p.duration);
  s.left_m = seg.left0;
  s.right_m = seg.right0;
  if (seg.p.lift) {
    const double a = tau / seg.p.duration;
    const PlanarPose& b = seg.p.lift_to;
    s.position = Vec3{seg.start.x + a * (b.x - seg.start.x), seg.start.y + a * (b.y - seg.start.y),
                      kLiftHeight * std::sin(kPi * a)};
    s.yaw = seg.start.yaw + a * (b.yaw - seg.start.yaw);
    s.lifted = a > 0.0 && a < 1.0;
    return s;
  }
  const PlanarPose p = integrate(seg.start, seg.p.v, seg.p.w, tau);
  s.position = Vec3{p.x, p.y, 0.0};
  s.yaw = p.yaw;
  s.left_m += (seg.p.v - 0.5 * seg.p.w * wheel_base_) * tau;
  s.right_m += (seg.p.v + 0.5 * seg.p.w * wheel_base_) * tau;
  return s;
}

std::vector<std::pair<double, double>> Trajectory::lift_intervals() const {
  std::vector<std::pair<double, double>> out;
  for (const Segment& s : segments_) {
    if (s.p.lift) {
      out.emplace_back(s.t0, s.t0 + s.p.duration);
    }
  }
  return out;
}

Pose3 Trajectory::body_pose(const TrueState& s) {
  return Pose3{rot_z(s.yaw), s.position};
}

PathPlan plan_path(const Scenario& sc, Random& rng) {
  PathPlan plan;
  if (sc.path.type == "wander") {
    plan.primitives = wander(sc, rng, plan.start);
  } else if (sc.path.type == "waypoints") {
    plan.primitives = waypoints(sc, plan.start);
  } else if (sc.path.type == "calibration") {
    plan.primitives = calibration_drive(sc, plan.start);
  } else if (sc.path.type == "standstill") {
    plan.start = PlanarPose{0.5 * sc.world.size.x, 0.5 * sc.world.size.y, 0.0};
    plan.primitives = {motion(sc.duration_s, 0.0, 0.0)};
  } else {
    plan.primitives = boustrophedon(sc, plan.start);
  }
  auto& prims = plan.primitives;
  if (sc.path.kidnap_at_s > 0.0 && sc.path.kidnap_skip_s > 0.0) {
    const PlanarPose from = pose_at(prims, plan.start, sc.path.kidnap_at_s);
    PlanarPose to = pose_at(prims, plan.start, sc.path.kidnap_at_s + sc.path.kidnap_skip_s);
    const std::size_t a = split_at(prims, sc.path.kidnap_at_s);
    const std::size_t b = split_at(prims, sc.path.kidnap_at_s + sc.path.kidnap_skip_s);
    // Keep the yaw continuous (unwrapped) through the lift: carried by the shortest rotation.
    to.yaw = from.yaw + wrap_angle(to.yaw - from.yaw);
    Primitive lift = motion(sc.path.lift_duration_s, 0.0, 0.0);
    lift.lift = true;
    lift.lift_to = to;
    prims.erase(prims.begin() + static_cast<std::ptrdiff_t>(a),
                prims.begin() + static_cast<std::ptrdiff_t>(b));
    prims.insert(prims.begin() + static_cast<std::ptrdiff_t>(a), lift);
    // Primitives after the lift integrate from `to`; their headings follow the lift's yaw,
    // which differs from the original by a multiple of 2 pi at most.
  }
  // Stops, latest first so that earlier times stay valid.
  std::vector<StopSpec> stops = sc.path.stops;
  std::sort(stops.begin(), stops.end(),
            [](const StopSpec& x, const StopSpec& y) { return x.at_s > y.at_s; });
  for (const StopSpec& s : stops) {
    if (s.duration_s <= 0.0) {
      continue;
    }
    const std::size_t i = split_at(prims, s.at_s);
    prims.insert(prims.begin() + static_cast<std::ptrdiff_t>(i), motion(s.duration_s, 0.0, 0.0));
  }
  if (sc.duration_s > 0.0) {
    const std::size_t end = split_at(prims, sc.duration_s);
    prims.erase(prims.begin() + static_cast<std::ptrdiff_t>(end), prims.end());
  }
  return plan;
}

}  // namespace cleanslam::sim_hal::sim
