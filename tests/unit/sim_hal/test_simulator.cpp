#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include "cleanslam/readers/csv.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/dataset_source.hpp"
#include "cleanslam/sim_hal/sim/random.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/sim_math.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"
#include "cleanslam/sim_hal/sim/trajectory.hpp"
#include "sim_test_files.hpp"

namespace fs = std::filesystem;
using namespace cleanslam;
namespace sim = cleanslam::sim_hal::sim;

namespace {

using sim_test::scenario;
using sim_test::slurp;
using sim_test::TempDir;
using sim_test::with;

// All noise sources off.
const std::vector<std::string> kNoiseFree = {
    "gyro.noise_density=0",        "gyro.initial_bias=0",         "gyro.bias_walk=0",
    "gyro.scale_error=0",          "encoders.scale_error_left=0", "encoders.scale_error_right=0",
    "encoders.wheel_base_error=0", "encoders.distance_noise=0",   "encoders.slip_rate_hz=0",
    "camera.pixel_noise=0",        "camera.jitter_s=0",           "camera.outlier_probability=0"};

// Rotation matrix of a unit quaternion (w, x, y, z), written out independently of sim_math.
std::array<double, 9> quat_to_matrix(const std::array<double, 4>& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

}  // namespace

TEST(SimRandom, DeterministicAndRoughlyNormal) {
  sim::Random a(42, 3), b(42, 3), c(43, 3), d(42, 4);
  EXPECT_EQ(a.next(), b.next());
  EXPECT_NE(a.next(), c.next());
  EXPECT_NE(b.next(), d.next());
  sim::Random r(7);
  double sum = 0.0, sum2 = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double g = r.gaussian();
    sum += g;
    sum2 += g * g;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(sum2 / n, 1.0, 0.02);
  for (int i = 0; i < 1000; ++i) {
    const double u = r.uniform();
    ASSERT_TRUE(u >= 0.0 && u < 1.0);
  }
}

TEST(SimMath, QuaternionOfRotation) {
  for (double yaw : {0.0, 0.3, 2.0, -3.0, std::numbers::pi}) {
    for (double pitch : {0.0, 0.4, -1.2}) {
      const sim::Mat3 r = sim::rot_z(yaw) * sim::rot_y(pitch) * sim::rot_x(0.7);
      const auto q = sim::quaternion_wxyz(r);
      const auto m = quat_to_matrix(q);
      for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 3; ++j) {
          EXPECT_NEAR(m[3 * i + j], r.m[i][j], 1e-12);
        }
      }
    }
  }
  EXPECT_NEAR(sim::wrap_angle(3.0 * std::numbers::pi), std::numbers::pi, 1e-12);
  EXPECT_NEAR(sim::wrap_angle(-0.5), -0.5, 1e-15);
}

TEST(SimTrajectory, ArcIntegrationMatchesSmallSteps) {
  sim::PlanarPose p{1.0, 2.0, 0.3};
  const double v = 0.2, w = 0.5, t = 3.0;
  sim::PlanarPose q = p;
  const int n = 300000;
  for (int i = 0; i < n; ++i) {
    const double dt = t / n;
    q.x += v * dt * std::cos(q.yaw + 0.5 * w * dt);
    q.y += v * dt * std::sin(q.yaw + 0.5 * w * dt);
    q.yaw += w * dt;
  }
  const auto e = sim::integrate(p, v, w, t);
  EXPECT_NEAR(e.x, q.x, 1e-9);
  EXPECT_NEAR(e.y, q.y, 1e-9);
  EXPECT_NEAR(e.yaw, q.yaw, 1e-9);
}

TEST(SimScenario, BuiltInsLoadAndDescribeTheRequiredWorlds) {
  const auto names = sim::builtin_scenario_names();
  for (const char* n :
       {"default-room", "corridor", "poor-texture", "person-walking", "kidnapped",
        "kidnapped-across", "standstills", "sparse-poor-odometry", "realistic-camera"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
    auto sc = sim::load_scenario(n);
    ASSERT_TRUE(sc.ok()) << n << ": " << sc.error();
    EXPECT_EQ(sc->name, n);
  }
  const auto room = scenario("default-room", {});
  EXPECT_DOUBLE_EQ(room.world.size.x, 6.0);
  EXPECT_DOUBLE_EQ(room.world.size.y, 5.0);
  EXPECT_DOUBLE_EQ(room.world.size.z, 2.5);
  sim::Random rng(room.seed, 2);
  const auto plan = sim::plan_path(room, rng);
  const sim::Trajectory traj(plan.primitives, plan.start, room.robot.wheel_base);
  EXPECT_GE(traj.length(), 30.0);
  for (double t = 0.0; t < traj.duration(); t += 0.5) {
    const auto s = traj.at(t);
    ASSERT_GE(s.position.x, room.path.margin - 1e-9);
    ASSERT_LE(s.position.x, room.world.size.x - room.path.margin + 1e-9);
    ASSERT_GE(s.position.y, room.path.margin - 1e-9);
    ASSERT_LE(s.position.y, room.world.size.y - room.path.margin + 1e-9);
  }
  const auto sparse = scenario("sparse-poor-odometry", {});
  EXPECT_EQ(sparse.landmarks.posts, 15);
  EXPECT_DOUBLE_EQ(sparse.duration_s, 900.0);
}

TEST(SimScenario, OverridesAndErrors) {
  auto sc =
      sim::load_scenario("default-room", {"camera.rate_hz=1", "world.size=[8, 6, 3]", "seed=17"});
  ASSERT_TRUE(sc.ok()) << sc.error();
  EXPECT_DOUBLE_EQ(sc->camera.rate_hz, 1.0);
  EXPECT_DOUBLE_EQ(sc->world.size.x, 8.0);
  EXPECT_EQ(sc->seed, 17U);
  auto typo = sim::load_scenario("default-room", {"camera.rate=1"});
  ASSERT_FALSE(typo.ok());
  EXPECT_NE(typo.error().find("camera.rate: unknown key"), std::string::npos) << typo.error();
  auto bad = sim::load_scenario("default-room", {"camera.rate_hz=fast"});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("camera.rate_hz: expected a number, got \"fast\""), std::string::npos)
      << bad.error();
  auto noeq = sim::load_scenario("default-room", {"camera.rate_hz"});
  EXPECT_FALSE(noeq.ok());
  auto missing = sim::load_scenario("no-such-scenario");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("built in: "), std::string::npos) << missing.error();
  auto neg = sim::load_scenario("default-room", {"gyro.rate_hz=0"});
  EXPECT_FALSE(neg.ok());
}

// Each of these wrote a dataset before: with a negative noise (and a calibration stating another),
// an outlier probability of 2, 1.8 GB of frames at 1e4 Hz, or gigabytes over hours (a world of
// 1e6 m, 1e8 landmarks).
TEST(SimScenario, NoisesProbabilitiesAndRatesOutsideTheirRangeAreErrors) {
  const struct {
    const char* set;
    const char* error;
  } cases[] = {
      {"gyro.noise_density=-1", "gyro.noise_density: -1 is out of range [0, 1]"},
      {"camera.pixel_noise=-3", "camera.pixel_noise: -3 is out of range [0, 100]"},
      {"encoders.distance_noise=-0.5", "encoders.distance_noise: -0.5 is out of range [0, 1]"},
      {"camera.outlier_probability=2", "camera.outlier_probability: 2 is out of range [0, 1]"},
      {"camera.rate_hz=1e4", "camera.rate_hz: 10000 is out of range (0, 100]"},
      {"encoders.scale_error_left=-2", "encoders.scale_error_left: -2 is out of range [-0.5, 0.5]"},
      {"camera.min_range=9", "camera.min_range: 9 is out of range [0, 5]"},
      {"world.size=[1e6, 1e6, 3]", "world.size: 1e+06 is out of range (0, 1000]"},
      {"landmarks.on_walls=100000000", "landmarks.on_walls: 100000000 is out of range [0, 100000]"},
      {"path.repeats=1000000", "path.repeats: 1000000 is out of range [1, 1000]"},
      {"camera.max_features=-5", "camera.max_features: -5 is out of range [0, 100000]"},
      {"duration_s=-5", "duration_s: -5 is out of range [0, 86400]"},
  };
  for (const auto& c : cases) {
    auto sc = sim::load_scenario("default-room", {c.set});
    ASSERT_FALSE(sc.ok()) << c.set;
    EXPECT_NE(sc.error().find(c.error), std::string::npos) << sc.error();
  }
  for (const char* name : {"corridor", "default-room", "kidnapped", "person-walking",
                           "poor-texture", "sparse-poor-odometry", "standstills"}) {
    EXPECT_TRUE(sim::load_scenario(name).ok()) << name;
  }
}

TEST(SimScenario, FileWithBase) {
  TempDir dir;
  fs::create_directories(dir.str());
  std::ofstream(dir.sub("mine.yaml")) << "base: corridor\nname: mine\ncamera:\n  rate_hz: 1.0\n";
  auto sc = sim::load_scenario(dir.sub("mine.yaml"));
  ASSERT_TRUE(sc.ok()) << sc.error();
  EXPECT_EQ(sc->name, "mine");
  EXPECT_DOUBLE_EQ(sc->world.size.x, 20.0);
  EXPECT_DOUBLE_EQ(sc->camera.rate_hz, 1.0);
  EXPECT_DOUBLE_EQ(sc->camera.tilt_deg, 10.0);
}

// A boustrophedon over 1000 m x 1000 m takes months: refused before anything is written.
TEST(Simulator, APathOfMoreThanADayIsRefusedBeforeWriting) {
  TempDir dir;
  const auto sc = scenario("default-room", {"world.size=[1000, 1000, 3]"});
  const auto r = sim::simulate(sc, dir.sub("out"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("more than a day"), std::string::npos) << r.error();
  EXPECT_FALSE(fs::exists(dir.sub("out")));
}

TEST(Simulator, DeterministicForASeed) {
  TempDir dir;
  const auto sc = scenario("person-walking", {"duration_s=40"});
  auto sc2 = sc;
  sc2.seed = sc.seed + 1;
  ASSERT_TRUE(sim::simulate(sc, dir.sub("a")).ok());
  ASSERT_TRUE(sim::simulate(sc, dir.sub("b")).ok());
  ASSERT_TRUE(sim::simulate(sc2, dir.sub("c")).ok());
  for (const char* f : {"gyro.csv", "encoders.csv", "features.csv", "groundtruth.csv",
                        "sensors.yaml", "sim_landmarks.csv"}) {
    EXPECT_EQ(slurp(dir.sub(std::string("a/") + f)), slurp(dir.sub(std::string("b/") + f))) << f;
  }
  EXPECT_NE(slurp(dir.sub("a/gyro.csv")), slurp(dir.sub("c/gyro.csv")));
  EXPECT_NE(slurp(dir.sub("a/features.csv")), slurp(dir.sub("c/features.csv")));
}

TEST(Simulator, WritesADatasetTheReaderAccepts) {
  TempDir dir;
  const auto sc = scenario("default-room", {"duration_s=60"});
  auto sum = sim::simulate(sc, dir.str());
  ASSERT_TRUE(sum.ok()) << sum.error();
  auto d = readers::load_dataset(dir.str());
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_TRUE(d->warnings.empty());
  EXPECT_EQ(static_cast<int>(d->gyro.size()), sum->gyro_samples);
  EXPECT_NEAR(static_cast<double>(d->gyro.size()), 60.0 * 100.0, 2.0);
  EXPECT_NEAR(static_cast<double>(d->encoders.size()), 60.0 * 20.0, 2.0);
  EXPECT_NEAR(static_cast<double>(d->groundtruth.size()), 60.0 * 100.0, 2.0);
  EXPECT_TRUE(d->has_features);
  EXPECT_GT(sum->mean_features, 3.0);
  for (const auto& f : d->features) {
    ASSERT_GE(f.observation.u_px, 0.0);
    ASSERT_LE(f.observation.u_px, 319.0);
    ASSERT_GE(f.observation.v_px, 0.0);
    ASSERT_LE(f.observation.v_px, 239.0);
  }
}

// With the noise off, every feature is the projection of its landmark through the ground-truth
// pose and the T_body_cam that sensors.yaml gives, computed here independently.
TEST(Simulator, FeaturesAreProjectionsThroughTheWrittenCalibration) {
  TempDir dir;
  const auto sc = scenario("default-room", with(kNoiseFree, {"duration_s=80"}));
  ASSERT_TRUE(sim::simulate(sc, dir.str()).ok());
  auto d = readers::load_dataset(dir.str());
  ASSERT_TRUE(d.ok()) << d.error();
  std::map<std::int64_t, std::array<double, 3>> lm;
  ASSERT_TRUE(readers::read_csv(dir.sub("sim_landmarks.csv"),
                                readers::CsvSpec{{"id", "x_m", "y_m", "z_m"}, {}},
                                [&](const readers::CsvRow& r) -> std::string {
                                  lm[*r.integer(0)] = {*r.number(1), *r.number(2), *r.number(3)};
                                  return {};
                                })
                  .ok());
  const auto& T = d->calibration.camera.T_body_cam;
  // The camera looks forward, 10 degrees up, 0.10 m ahead of the axle and 0.10 m up.
  EXPECT_NEAR(T[3], 0.10, 1e-12);
  EXPECT_NEAR(T[11], 0.10, 1e-12);
  EXPECT_NEAR(std::atan2(T[10], T[2]), 10.0 * std::numbers::pi / 180.0, 1e-12);
  const auto& cam = d->calibration.camera;
  std::size_t gi = 0;
  int checked = 0;
  for (const auto& f : d->features) {
    while (gi + 1 < d->groundtruth.size() && d->groundtruth[gi + 1].t_ns <= f.t_ns) {
      ++gi;
    }
    const auto& g0 = d->groundtruth[gi];
    const auto& g1 = d->groundtruth[std::min(gi + 1, d->groundtruth.size() - 1)];
    const double a = g1.t_ns == g0.t_ns ? 0.0
                                        : static_cast<double>(f.t_ns - g0.t_ns) /
                                              static_cast<double>(g1.t_ns - g0.t_ns);
    std::array<double, 4> q{};
    for (std::size_t i = 0; i < 4; ++i) {
      q[i] = (1 - a) * g0.orientation_wxyz[i] + a * g1.orientation_wxyz[i];
    }
    const double qn = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (double& v : q) {
      v /= qn;
    }
    std::array<double, 3> p{};
    for (std::size_t i = 0; i < 3; ++i) {
      p[i] = (1 - a) * g0.position_m[i] + a * g1.position_m[i];
    }
    const auto R = quat_to_matrix(q);
    const auto& L = lm.at(f.observation.track_id);
    // Landmark in the body frame, then in the camera frame: p_c = R_bc^T (p_b - t_bc).
    double pb[3], pc[3];
    for (std::size_t i = 0; i < 3; ++i) {
      pb[i] = R[0 + i] * (L[0] - p[0]) + R[3 + i] * (L[1] - p[1]) + R[6 + i] * (L[2] - p[2]);
    }
    const double t[3] = {T[3], T[7], T[11]};
    for (std::size_t i = 0; i < 3; ++i) {
      pc[i] = T[0 + i] * (pb[0] - t[0]) + T[4 + i] * (pb[1] - t[1]) + T[8 + i] * (pb[2] - t[2]);
    }
    ASSERT_GT(pc[2], 0.0);
    const double u = cam.fx * pc[0] / pc[2] + cam.cx;
    const double v = cam.fy * pc[1] / pc[2] + cam.cy;
    EXPECT_NEAR(u, f.observation.u_px, 0.05) << f.t_ns << " id " << f.observation.track_id;
    EXPECT_NEAR(v, f.observation.v_px, 0.05) << f.t_ns << " id " << f.observation.track_id;
    ++checked;
  }
  EXPECT_GT(checked, 300);
}

// With the noise off, dead reckoning from gyro and encoders follows the ground truth.
TEST(Simulator, NoiseFreeOdometryReproducesGroundTruth) {
  TempDir dir;
  const auto sc = scenario("default-room", with(kNoiseFree, {"duration_s=120"}));
  ASSERT_TRUE(sim::simulate(sc, dir.str()).ok());
  auto d = readers::load_dataset(dir.str());
  ASSERT_TRUE(d.ok()) << d.error();
  const auto& cal = d->calibration;
  double yaw = 0.0, x = d->groundtruth[0].position_m[0], y = d->groundtruth[0].position_m[1];
  hal::TimeNs t_prev = d->groundtruth[0].t_ns;
  std::size_t gi = 0;
  auto yaw_at = [&](hal::TimeNs t) {
    // Integrate the gyro up to t (samples are mean rates over the previous 10 ms).
    while (gi < d->gyro.size() && d->gyro[gi].t_ns <= t) {
      yaw += d->gyro[gi].wz_rad_s * hal::to_seconds(d->gyro[gi].t_ns - t_prev);
      t_prev = d->gyro[gi].t_ns;
      ++gi;
    }
    return yaw;
  };
  double prev_yaw = 0.0;
  for (std::size_t k = 1; k < d->encoders.size(); ++k) {
    const double dl = hal::tick_delta(d->encoders[k].left_ticks, d->encoders[k - 1].left_ticks) /
                      cal.wheels.ticks_per_meter_left;
    const double dr = hal::tick_delta(d->encoders[k].right_ticks, d->encoders[k - 1].right_ticks) /
                      cal.wheels.ticks_per_meter_right;
    const double yw = yaw_at(d->encoders[k].t_ns);
    const double mid = 0.5 * (prev_yaw + yw);
    prev_yaw = yw;
    x += 0.5 * (dl + dr) * std::cos(mid);
    y += 0.5 * (dl + dr) * std::sin(mid);
  }
  const auto& last = d->groundtruth.back();
  EXPECT_NEAR(x, last.position_m[0], 0.03);
  EXPECT_NEAR(y, last.position_m[1], 0.03);
  const double gt_yaw = 2.0 * std::atan2(last.orientation_wxyz[3], last.orientation_wxyz[0]);
  EXPECT_NEAR(sim::wrap_angle(prev_yaw - gt_yaw), 0.0, 1e-3);
}

TEST(Simulator, GyroNoiseAndBiasFollowTheScenario) {
  TempDir dir;
  // Standing still for 200 s: the gyro shows bias + white noise only.
  const auto sc = scenario(
      "default-room", {"duration_s=200", "path.stops=[{at_s: 0, duration_s: 300}]",
                       "gyro.noise_density=0.002", "gyro.initial_bias=0.003", "gyro.bias_walk=0"});
  ASSERT_TRUE(sim::simulate(sc, dir.str()).ok());
  auto d = readers::load_dataset(dir.str());
  ASSERT_TRUE(d.ok()) << d.error();
  double sum = 0.0, sum2 = 0.0;
  for (const auto& g : d->gyro) {
    sum += g.wz_rad_s;
  }
  const double mean = sum / static_cast<double>(d->gyro.size());
  for (const auto& g : d->gyro) {
    sum2 += (g.wz_rad_s - mean) * (g.wz_rad_s - mean);
  }
  const double sd = std::sqrt(sum2 / static_cast<double>(d->gyro.size()));
  EXPECT_NEAR(mean, 0.003, 0.0006);  // 4 sigma of the mean of 20000 samples
  EXPECT_NEAR(sd, 0.002 * std::sqrt(100.0), 0.001);
  // The encoders do not move while standing.
  EXPECT_EQ(d->encoders.front().left_ticks, d->encoders.back().left_ticks);
  EXPECT_EQ(d->encoders.front().right_ticks, d->encoders.back().right_ticks);
}

TEST(Simulator, TickCountersWrapAt32Bits) {
  TempDir dir;
  const auto sc = scenario("default-room", {"duration_s=30", "robot.initial_ticks=2147480000"});
  ASSERT_TRUE(sim::simulate(sc, dir.str()).ok());
  auto e = readers::read_encoders_csv(dir.sub("encoders.csv"));
  ASSERT_TRUE(e.ok()) << e.error();
  bool wrapped = false;
  std::int64_t total = 0;
  for (std::size_t k = 1; k < e->size(); ++k) {
    wrapped = wrapped || ((*e)[k].left_ticks < 0 && (*e)[k - 1].left_ticks > 0);
    const auto dl = hal::tick_delta((*e)[k].left_ticks, (*e)[k - 1].left_ticks);
    const auto dr = hal::tick_delta((*e)[k].right_ticks, (*e)[k - 1].right_ticks);
    ASSERT_LT(std::abs(dl), 200);
    ASSERT_GE(dl + dr, -2);  // forward runs and turns in place, never reversing
    total += dl + dr;
  }
  EXPECT_TRUE(wrapped);
  EXPECT_NEAR(0.5 * static_cast<double>(total) / 4000.0, 0.2 * 30.0, 0.5);
}

TEST(Simulator, KidnappedRobotIsLiftedAndMoved) {
  TempDir dir;
  const auto sc = scenario("kidnapped", {"duration_s=200"});
  ASSERT_TRUE(sim::simulate(sc, dir.str()).ok());
  auto d = readers::load_dataset(dir.str());
  ASSERT_TRUE(d.ok()) << d.error();
  double max_z = 0.0;
  hal::TimeNs lift_start = -1, lift_end = -1;
  for (const auto& g : d->groundtruth) {
    if (g.position_m[2] > 1e-6) {
      if (lift_start < 0) {
        lift_start = g.t_ns;
      }
      lift_end = g.t_ns;
    }
    max_z = std::max(max_z, g.position_m[2]);
  }
  EXPECT_GT(max_z, 0.1);
  ASSERT_GT(lift_start, 0);
  EXPECT_NEAR(hal::to_seconds(lift_end - lift_start), 3.0, 0.05);
  EXPECT_NEAR(hal::to_seconds(lift_start) - sc.start_time_s, 150.0, 0.05);
  // No wheel counts while in the air.
  std::int32_t before = 0, after = 0;
  for (const auto& e : d->encoders) {
    if (e.t_ns <= lift_start) {
      before = e.left_ticks;
    }
    if (e.t_ns <= lift_end) {
      after = e.left_ticks;
    }
  }
  EXPECT_LE(std::abs(hal::tick_delta(after, before)), 40);  // at most one sample's driving
  // The wheel-drop switch: lift.csv says when, and the source turns it into kLift events.
  ASSERT_EQ(d->lift.size(), 2U);
  EXPECT_TRUE(d->lift[0].lifted);
  EXPECT_FALSE(d->lift[1].lifted);
  EXPECT_NEAR(hal::to_seconds(d->lift[0].t_ns - lift_start), 0.0, 0.011);
  EXPECT_NEAR(hal::to_seconds(d->lift[1].t_ns - lift_end), 0.0, 0.011);
  auto src = readers::DatasetSource::open(dir.str());
  ASSERT_TRUE(src.ok()) << src.error();
  hal::SensorEvent ev;
  std::vector<bool> lifts;
  hal::TimeNs last = 0;
  while (src->read(ev)) {
    if (ev.kind == hal::SensorEvent::Kind::kLift) {
      lifts.push_back(ev.lifted);
      EXPECT_GE(src->next_event_time(), last);
    }
    last = src->next_event_time();
  }
  EXPECT_EQ(lifts, (std::vector<bool>{true, false}));
}

// Carried across the room: set down more than 4.5 m from where it was lifted, turned by about a
// quarter turn.
TEST(Simulator, KidnappedAcrossIsSetDownOnTheFarSide) {
  TempDir dir;
  const auto sc = scenario("kidnapped-across", {"duration_s=160"});
  ASSERT_TRUE(sim::simulate(sc, dir.str()).ok());
  auto d = readers::load_dataset(dir.str());
  ASSERT_TRUE(d.ok()) << d.error();
  ASSERT_EQ(d->lift.size(), 2U);
  const readers::GroundTruthPose* before = nullptr;
  const readers::GroundTruthPose* after = nullptr;
  for (const auto& g : d->groundtruth) {
    if (g.t_ns <= d->lift[0].t_ns) {
      before = &g;
    }
    if (after == nullptr && g.t_ns >= d->lift[1].t_ns) {
      after = &g;
    }
  }
  ASSERT_NE(before, nullptr);
  ASSERT_NE(after, nullptr);
  const double dx = after->position_m[0] - before->position_m[0];
  const double dy = after->position_m[1] - before->position_m[1];
  EXPECT_GT(std::hypot(dx, dy), 4.5);
  const auto yaw = [](const readers::GroundTruthPose& g) {
    return 2.0 * std::atan2(g.orientation_wxyz[3], g.orientation_wxyz[0]);
  };
  const double turn = std::remainder(yaw(*after) - yaw(*before), 2.0 * M_PI);
  EXPECT_NEAR(std::abs(turn), M_PI / 2.0, 0.2);
}

TEST(Simulator, SparsePoorOdometryIsSparse) {
  TempDir dir;
  const auto sc = scenario("sparse-poor-odometry", {});
  auto sum = sim::simulate(sc, dir.str());
  ASSERT_TRUE(sum.ok()) << sum.error();
  EXPECT_NEAR(sum->duration_s, 900.0, 1e-6);
  EXPECT_GT(sum->path_length_m, 35.0);
  EXPECT_LT(sum->path_length_m, 70.0);
  EXPECT_EQ(sum->landmarks, 15);
  EXPECT_LT(sum->mean_features, 1.0);
  EXPECT_GT(sum->longest_gap_s, 20.0);
  auto d = readers::load_dataset(dir.str());
  ASSERT_TRUE(d.ok()) << d.error();
  std::map<hal::TimeNs, int> per_frame;
  for (const auto& f : d->features) {
    ++per_frame[f.t_ns];
  }
  for (const auto& [t, n] : per_frame) {
    EXPECT_LE(n, 3) << t;
  }
  EXPECT_DOUBLE_EQ(d->calibration.camera.fx, 220.0);
}
