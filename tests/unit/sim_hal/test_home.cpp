// The simulated home: interior walls with doors, waypoint paths, world.seed and objects moved on a
// second day.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include "cleanslam/readers/csv.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/sim_hal/sim/random.hpp"
#include "cleanslam/sim_hal/sim/renderer.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"
#include "cleanslam/sim_hal/sim/trajectory.hpp"
#include "cleanslam/sim_hal/sim/world.hpp"
#include "sim_test_files.hpp"

namespace fs = std::filesystem;
using namespace cleanslam;
namespace sim = cleanslam::sim_hal::sim;

namespace {

using sim_test::scenario;
using sim_test::slurp;
using sim_test::TempDir;
using sim_test::with;

sim::World world_of(const sim::Scenario& sc) {
  sim::Random rng(sc.world_seed(), sim::stream::kWorld);
  return sim::World(sc, rng);
}

sim::Trajectory trajectory_of(const sim::Scenario& sc) {
  sim::Random rng(sc.seed, sim::stream::kPath);
  const auto plan = sim::plan_path(sc, rng);
  return sim::Trajectory(plan.primitives, plan.start, sc.robot.wheel_base);
}

// The default room with one interior wall at x = 3 from the south wall to y = 3.5 (a door from
// there to the north wall) and no furniture.
const std::vector<std::string> kWallRoom = {
    "world.furniture=[]", "world.walls=[{min: [2.9, 0.0, 0.0], max: [3.1, 3.5, 2.5]}]"};

bool on_box_surface(const sim::Box& b, sim::Vec3 p) {
  constexpr double e = 1e-9;
  const bool within = p.x >= b.min.x - e && p.x <= b.max.x + e && p.y >= b.min.y - e &&
                      p.y <= b.max.y + e && p.z >= b.min.z - e && p.z <= b.max.z + e;
  const bool on_face = std::abs(p.x - b.min.x) < e || std::abs(p.x - b.max.x) < e ||
                       std::abs(p.y - b.min.y) < e || std::abs(p.y - b.max.y) < e ||
                       std::abs(p.z - b.max.z) < e;
  return within && on_face;
}

// The rooms of a world: the floor cells (5 cm) farther than `clearance` from the outer and the
// interior walls (furniture ignored), grouped into 4-connected regions; -1 for a cell too close.
struct Floor {
  double cell = 0.05;
  int nx = 0, ny = 0;
  std::vector<int> region;
  int regions = 0;
  [[nodiscard]] int at(double x, double y) const {
    const int i = static_cast<int>(x / cell), j = static_cast<int>(y / cell);
    if (i < 0 || j < 0 || i >= nx || j >= ny) {
      return -1;
    }
    return region[static_cast<std::size_t>(j * nx + i)];
  }
};

Floor rooms(const sim::Scenario& sc, double clearance) {
  Floor f;
  f.nx = static_cast<int>(std::round(sc.world.size.x / f.cell));
  f.ny = static_cast<int>(std::round(sc.world.size.y / f.cell));
  f.region.assign(static_cast<std::size_t>(f.nx * f.ny), -1);
  std::vector<bool> free(f.region.size(), false);
  for (int j = 0; j < f.ny; ++j) {
    for (int i = 0; i < f.nx; ++i) {
      const double x = (i + 0.5) * f.cell, y = (j + 0.5) * f.cell;
      double d = std::min({x, y, sc.world.size.x - x, sc.world.size.y - y});
      for (const sim::Box& w : sc.world.walls) {
        const double dx = std::max({w.min.x - x, 0.0, x - w.max.x});
        const double dy = std::max({w.min.y - y, 0.0, y - w.max.y});
        d = std::min(d, std::hypot(dx, dy));
      }
      free[static_cast<std::size_t>(j * f.nx + i)] = d > clearance;
    }
  }
  for (std::size_t start = 0; start < free.size(); ++start) {
    if (!free[start] || f.region[start] >= 0) {
      continue;
    }
    std::vector<std::size_t> stack{start};
    f.region[start] = f.regions;
    while (!stack.empty()) {
      const std::size_t c = stack.back();
      stack.pop_back();
      const int i = static_cast<int>(c) % f.nx, j = static_cast<int>(c) / f.nx;
      const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
      for (int k = 0; k < 4; ++k) {
        const int a = i + di[k], b = j + dj[k];
        if (a < 0 || b < 0 || a >= f.nx || b >= f.ny) {
          continue;
        }
        const std::size_t n = static_cast<std::size_t>(b * f.nx + a);
        if (free[n] && f.region[n] < 0) {
          f.region[n] = f.regions;
          stack.push_back(n);
        }
      }
    }
    ++f.regions;
  }
  return f;
}

}  // namespace

TEST(SimWaypoints, ThePathRunsStraightFromPointToPointAndTurnsInPlace) {
  const std::vector<std::array<double, 2>> w = {{1.0, 1.0}, {4.0, 1.2}, {4.5, 3.5},
                                                {1.2, 3.8}, {1.2, 3.8}, {2.0, 2.0}};
  const auto sc = scenario("default-room", {"world.furniture=[]", "path.type=waypoints",
                                            "path.waypoints=[[1, 1], [4, 1.2], [4.5, 3.5], [1.2, "
                                            "3.8], [1.2, 3.8], [2, 2]]"});
  sim::Random rng(sc.seed, sim::stream::kPath);
  const auto plan = sim::plan_path(sc, rng);
  // The start: at the first point, facing the second.
  EXPECT_DOUBLE_EQ(plan.start.x, 1.0);
  EXPECT_DOUBLE_EQ(plan.start.y, 1.0);
  EXPECT_NEAR(plan.start.yaw, std::atan2(0.2, 3.0), 1e-12);
  const sim::Trajectory traj(plan.primitives, plan.start, sc.robot.wheel_base);
  // Each straight run ends on the next distinct waypoint, heading along its segment all the way;
  // the turns between them are in place.
  std::size_t next = 1;
  double t = 0.0, length = 0.0;
  for (const auto& p : plan.primitives) {
    const auto s0 = traj.at(t);
    const auto s1 = traj.at(t + p.duration);
    if (p.v > 0.0) {
      while (next < w.size() &&
             std::hypot(w[next][0] - w[next - 1][0], w[next][1] - w[next - 1][1]) < 1e-9) {
        ++next;
      }
      ASSERT_LT(next, w.size());
      const double heading = std::atan2(w[next][1] - w[next - 1][1], w[next][0] - w[next - 1][0]);
      for (double f : {0.0, 0.5, 1.0}) {
        EXPECT_NEAR(sim::wrap_angle(traj.at(t + f * p.duration).yaw - heading), 0.0, 1e-9)
            << "segment " << next;
      }
      EXPECT_NEAR(s1.position.x, w[next][0], 0.01) << "waypoint " << next;
      EXPECT_NEAR(s1.position.y, w[next][1], 0.01) << "waypoint " << next;
      EXPECT_NEAR(p.v, sc.path.speed, 1e-12);
      length += std::hypot(w[next][0] - w[next - 1][0], w[next][1] - w[next - 1][1]);
      ++next;
    } else {
      EXPECT_NEAR(std::hypot(s1.position.x - s0.position.x, s1.position.y - s0.position.y), 0.0,
                  1e-12);
      EXPECT_NEAR(std::abs(p.w), sc.path.turn_rate, 1e-12);
    }
    t += p.duration;
  }
  EXPECT_EQ(next, w.size());
  EXPECT_NEAR(traj.length(), length, 1e-9);
}

TEST(SimWaypoints, APathThroughAWallOrOutOfTheWorldIsRefused) {
  // Through the wall.
  auto through = sim::load_scenario(
      "default-room",
      with(kWallRoom, {"path.type=waypoints", "path.waypoints=[[1, 4.2], [1, 1], [5, 1]]"}));
  ASSERT_FALSE(through.ok());
  EXPECT_NE(through.error().find("path.waypoints[1] -> [2]: the segment (1, 1) -> (5, 1) runs "
                                 "through world.walls[0]"),
            std::string::npos)
      << through.error();
  EXPECT_EQ(through.error().find("path.waypoints[0] -> [1]"), std::string::npos);
  // Past its end closer than the robot's radius (0.2 m): refused too.
  auto grazing = sim::load_scenario(
      "default-room",
      with(kWallRoom, {"path.type=waypoints", "path.waypoints=[[1, 3.62], [5, 3.62]]"}));
  ASSERT_FALSE(grazing.ok());
  EXPECT_NE(grazing.error().find("path.waypoints[0] -> [1]"), std::string::npos);
  // Through the door, clear of it: accepted.
  EXPECT_TRUE(sim::load_scenario("default-room", with(kWallRoom, {"path.type=waypoints",
                                                                  "path.waypoints=[[1, 1], "
                                                                  "[1, 4.2], [5, 4.2], [5, 1]]"}))
                  .ok());
  // Through a piece of furniture at the place world.moved puts it.
  auto moved = sim::load_scenario("default-room",
                                  {"path.type=waypoints", "path.waypoints=[[3, 1], [3, 4]]",
                                   "world.furniture=[{min: [0.5, 2.0, 0.0], max: [1.0, 3.0, 0.5]}]",
                                   "world.moved=[{furniture: 0, by: [2.0, 0.0]}]"});
  ASSERT_FALSE(moved.ok());
  EXPECT_NE(moved.error().find("runs through world.furniture[0]"), std::string::npos)
      << moved.error();
  // A point outside the world.
  auto outside = sim::load_scenario(
      "default-room", {"path.type=waypoints", "path.waypoints=[[1, 1], [7, 1], [1, 2]]"});
  ASSERT_FALSE(outside.ok());
  EXPECT_NE(outside.error().find("path.waypoints[1]: (7, 1) is outside the world"),
            std::string::npos)
      << outside.error();
  auto one = sim::load_scenario("default-room", {"path.type=waypoints", "path.waypoints=[[1, 1]]"});
  ASSERT_FALSE(one.ok());
  EXPECT_NE(one.error().find("path.waypoints: a waypoints path needs two points"),
            std::string::npos);
  auto flat =
      sim::load_scenario("default-room", {"world.walls=[{min: [1, 1, 0], max: [1, 2, 2.5]}]"});
  ASSERT_FALSE(flat.ok());
  EXPECT_NE(flat.error().find("world.walls[0]: min must be below max"), std::string::npos)
      << flat.error();
  auto bad_index = sim::load_scenario("default-room", {"world.moved=[{furniture: 4, by: [1, 0]}]"});
  ASSERT_FALSE(bad_index.ok());
  EXPECT_NE(bad_index.error().find("world.moved[0].furniture: 4 is not an index"),
            std::string::npos)
      << bad_index.error();
}

// Day 2 with another --seed: other sensor noise, the same landmarks and textures.
TEST(SimHome, WorldSeedKeepsTheWorldAcrossRunSeeds) {
  TempDir dir;
  const std::vector<std::string> base = {"duration_s=20"};
  const auto a = scenario("default-room", with(base, {"seed=1", "world.seed=7"}));
  const auto b = scenario("default-room", with(base, {"seed=2", "world.seed=7"}));
  const auto c = scenario("default-room", with(base, {"seed=2"}));
  ASSERT_TRUE(sim::simulate(a, dir.sub("a")).ok());
  ASSERT_TRUE(sim::simulate(b, dir.sub("b")).ok());
  ASSERT_TRUE(sim::simulate(c, dir.sub("c")).ok());
  EXPECT_EQ(slurp(dir.sub("a/sim_landmarks.csv")), slurp(dir.sub("b/sim_landmarks.csv")));
  EXPECT_NE(slurp(dir.sub("a/sim_landmarks.csv")), slurp(dir.sub("c/sim_landmarks.csv")));
  EXPECT_NE(slurp(dir.sub("a/features.csv")), slurp(dir.sub("b/features.csv")));
  EXPECT_NE(slurp(dir.sub("a/gyro.csv")), slurp(dir.sub("b/gyro.csv")));
  // The textures too.
  const sim::Renderer ra(a), rb(b), rc(c);
  int differ = 0;
  for (int surface : {0, 3, 5, 6}) {
    for (double u = 0.05; u < 4.0; u += 0.37) {
      EXPECT_EQ(ra.albedo(surface, u, 0.6 * u), rb.albedo(surface, u, 0.6 * u));
      differ += ra.albedo(surface, u, 0.6 * u) != rc.albedo(surface, u, 0.6 * u) ? 1 : 0;
    }
  }
  EXPECT_GT(differ, 10);
}

TEST(SimHome, MovedFurnitureTakesExactlyItsLandmarksAlong) {
  const auto day1 = scenario("home");
  const auto day2 = scenario("home-day2");
  ASSERT_EQ(day1.world_seed(), day2.world_seed());
  const sim::World w1 = world_of(day1), w2 = world_of(day2);
  ASSERT_EQ(w1.landmarks().size(), w2.landmarks().size());
  std::map<std::size_t, int> moved_per_box;
  int unmoved = 0;
  for (std::size_t i = 0; i < w1.landmarks().size(); ++i) {
    const auto& l1 = w1.landmarks()[i];
    const auto& l2 = w2.landmarks()[i];
    ASSERT_EQ(l1.id, l2.id);
    const sim::Vec3 d = l2.position - l1.position;
    if (sim::norm(d) == 0.0) {
      ++unmoved;
      for (std::size_t k = 0; k < day2.world.furniture.size(); ++k) {
        const bool moved_box = sim::norm(day2.world.furniture[k].moved_by) > 0.0;
        EXPECT_FALSE(moved_box && on_box_surface(day1.world.furniture[k], l1.position))
            << "landmark " << l1.id << " stayed behind furniture " << k;
      }
      continue;
    }
    // A landmark that moved lies on a moved box, and moved with it by exactly its move.
    bool explained = false;
    for (std::size_t k = 0; k < day2.world.furniture.size(); ++k) {
      const sim::Box& before = day1.world.furniture[k];
      const sim::Vec3 by = day2.world.furniture[k].moved_by;
      if (sim::norm(by) == 0.0 || !on_box_surface(before, l1.position)) {
        continue;
      }
      EXPECT_LT(sim::norm(d - by), 1e-12) << "landmark " << l1.id;
      EXPECT_TRUE(on_box_surface(w2.boxes()[k], l2.position)) << "landmark " << l1.id;
      ++moved_per_box[k];
      explained = true;
    }
    EXPECT_TRUE(explained) << "landmark " << l1.id << " moved but is on no moved box";
  }
  // Three objects moved, each with landmarks on it; every other landmark where it was.
  EXPECT_EQ(moved_per_box.size(), 3U);
  for (const auto& [k, n] : moved_per_box) {
    EXPECT_GT(n, 0) << "furniture " << k;
  }
  EXPECT_GT(unmoved, 300);
  for (std::size_t k = 0; k < day1.world.furniture.size(); ++k) {
    const bool moved = moved_per_box.count(k) > 0;
    EXPECT_EQ(w2.boxes()[k].min.x != w1.boxes()[k].min.x, moved) << "furniture " << k;
  }
  // sim_landmarks.csv holds the moved positions.
  TempDir dir;
  ASSERT_TRUE(sim::simulate(scenario("home-day2", {"duration_s=5"}), dir.sub("d2")).ok());
  std::map<std::int64_t, sim::Vec3> csv;
  ASSERT_TRUE(readers::read_csv(dir.sub("d2/sim_landmarks.csv"),
                                readers::CsvSpec{{"id", "x_m", "y_m", "z_m"}, {}},
                                [&](const readers::CsvRow& r) -> std::string {
                                  csv[*r.integer(0)] = {*r.number(1), *r.number(2), *r.number(3)};
                                  return {};
                                })
                  .ok());
  ASSERT_EQ(csv.size(), w2.landmarks().size());
  for (const auto& l : w2.landmarks()) {
    EXPECT_LT(sim::norm(csv.at(l.id) - l.position), 1e-12) << "landmark " << l.id;
  }
}

TEST(SimHome, IsAFlatOfRoomsJoinedByDoorsThatThePathsTourAndRevisit) {
  for (const char* name : {"home", "home-day2"}) {
    SCOPED_TRACE(name);
    const auto sc = scenario(name);
    const sim::World world = world_of(sc);
    EXPECT_GE(world.landmarks().size(), 300U);
    // Rooms: the floor more than 0.5 m from any wall falls apart at the 0.9 m doors; with the
    // robot's radius it is one piece.
    const Floor room = rooms(sc, 0.5);
    EXPECT_GE(room.regions, 4);
    EXPECT_EQ(rooms(sc, sc.robot.radius).regions, 1);
    // Landmarks on the interior walls, on both faces of them.
    int on_interior = 0;
    std::set<std::pair<double, double>> normals;
    for (const auto& l : world.landmarks()) {
      for (const sim::Box& w : sc.world.walls) {
        if (on_box_surface(w, l.position)) {
          ++on_interior;
          normals.insert({l.normal.x, l.normal.y});
          break;
        }
      }
    }
    EXPECT_GE(on_interior, 100);
    EXPECT_EQ(normals.size(), 4U);
    // The path visits every room, leaves one and comes back to it later (a loop to close), and
    // ends at the dock it left.
    const sim::Trajectory traj = trajectory_of(sc);
    EXPECT_GE(traj.duration(), 280.0);
    EXPECT_LE(traj.duration(), 600.0);
    std::vector<int> visits;
    for (double t = 0.0; t <= traj.duration(); t += 0.5) {
      const auto s = traj.at(t);
      const int r = room.at(s.position.x, s.position.y);
      if (r >= 0 && (visits.empty() || visits.back() != r)) {
        visits.push_back(r);
      }
    }
    EXPECT_EQ(std::set<int>(visits.begin(), visits.end()).size(),
              static_cast<std::size_t>(room.regions));
    std::map<int, int> entries;
    for (int r : visits) {
      ++entries[r];
    }
    int revisited = 0;
    for (const auto& [r, n] : entries) {
      revisited += n > 1 ? 1 : 0;
    }
    EXPECT_GE(revisited, 2);
    const auto end = traj.at(traj.duration());
    EXPECT_NEAR(end.position.x, sc.path.waypoints.front()[0], 1e-9);
    EXPECT_NEAR(end.position.y, sc.path.waypoints.front()[1], 1e-9);
  }
  // Both days leave the same dock pose.
  const auto a = trajectory_of(scenario("home")).at(0.0);
  const auto b = trajectory_of(scenario("home-day2")).at(0.0);
  EXPECT_EQ(a.position.x, b.position.x);
  EXPECT_EQ(a.position.y, b.position.y);
  EXPECT_NEAR(sim::wrap_angle(a.yaw - b.yaw), 0.0, 1e-12);
}

TEST(SimHome, AnInteriorWallHidesWhatIsBehindIt) {
  const auto open = scenario("default-room", {"world.furniture=[]", "camera.min_facing_cos=0"});
  const auto walled = scenario("default-room", with(kWallRoom, {"camera.min_facing_cos=0"}));
  // A landmark on the east wall, straight ahead of a camera at x = 1 looking east, behind the
  // interior wall at x = 3.
  std::vector<sim::Landmark> lm(1);
  lm[0].id = 5;
  lm[0].position = {6.0, 1.5, 0.2};
  lm[0].normal = {-1.0, 0.0, 0.0};
  const sim::Pose3 wc =
      sim::compose(sim::Pose3{sim::rot_z(0.0), {1.0, 1.5, 0.0}}, sim::body_to_camera(open.camera));
  EXPECT_EQ(sim::visible_landmarks(open.camera, world_of(open), lm, wc).size(), 1U);
  EXPECT_TRUE(sim::visible_landmarks(walled.camera, world_of(walled), lm, wc).empty());
  // Rendered: the wall, not the east wall behind it.
  EXPECT_EQ(sim::Renderer(open).surface_at(wc, 160, 119), 5);
  EXPECT_GE(sim::Renderer(walled).surface_at(wc, 160, 119), 6);
  // End to end, the wall closed from end to end: driving west of it, the robot observes no
  // landmark east of it, though it observes those on the wall's west face.
  TempDir dir;
  const auto sc =
      scenario("default-room",
               {"world.furniture=[]", "world.walls=[{min: [2.9, 0.0, 0.0], max: [3.1, 5.0, 2.5]}]",
                "path.type=waypoints",
                "path.waypoints=[[0.5, 0.5], [2.5, 0.6], [2.5, 3.0], [0.5, 3.0], [0.6, "
                "0.6], [2.5, 0.6]]",
                "landmarks.on_interior_walls=40"});
  ASSERT_TRUE(sim::simulate(sc, dir.sub("d")).ok());
  std::map<std::int64_t, double> x_of;
  ASSERT_TRUE(readers::read_csv(dir.sub("d/sim_landmarks.csv"),
                                readers::CsvSpec{{"id", "x_m", "y_m", "z_m"}, {}},
                                [&](const readers::CsvRow& r) -> std::string {
                                  x_of[*r.integer(0)] = *r.number(1);
                                  return {};
                                })
                  .ok());
  auto d = readers::load_dataset(dir.sub("d"));
  ASSERT_TRUE(d.ok()) << d.error();
  int west_face = 0, behind = 0, before = 0;
  for (const auto& f : d->features) {
    const double x = x_of.at(f.observation.track_id);
    if (x > 3.05) {
      ++behind;
    }
    if (std::abs(x - 2.9) < 1e-12) {
      ++west_face;
    }
    if (x < 2.9) {
      ++before;
    }
  }
  EXPECT_EQ(behind, 0);
  EXPECT_GT(west_face, 20);
  EXPECT_GT(before, 20);
}
