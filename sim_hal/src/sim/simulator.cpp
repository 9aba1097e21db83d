#include "cleanslam/sim_hal/sim/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <numbers>

#include "cleanslam/sim_hal/dataset_writer.hpp"
#include "cleanslam/sim_hal/sim/checkerboard_views.hpp"
#include "cleanslam/sim_hal/sim/frame_exposure.hpp"
#include "cleanslam/sim_hal/sim/random.hpp"
#include "cleanslam/sim_hal/sim/renderer.hpp"
#include "cleanslam/sim_hal/sim/trajectory.hpp"

namespace cleanslam::sim_hal::sim {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

hal::TimeNs to_ns(double s) {
  return static_cast<hal::TimeNs>(std::llround(s * 1e9));
}

std::int32_t wrap32(std::int64_t v) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(static_cast<std::uint64_t>(v)));
}

}  // namespace

readers::Status write_sim_truth(const Scenario& sc, const std::string& path) {
  using readers::format_double;
  const auto& e = sc.encoders;
  const auto& g = sc.gyro;
  const auto& c = sc.camera;
  std::ofstream out(path, std::ios::trunc);
  out << "# The simulator's true sensor constants (scenario " << sc.name << ", seed " << sc.seed
      << "), against which a\n# calibration (tools/calibrate) is checked; sensors.yaml holds the "
         "nominal ones.\nwheels:\n"
      << "  ticks_per_meter_left: "
      << format_double(sc.robot.ticks_per_meter * (1.0 + e.scale_error_left))
      << "   # robot.ticks_per_meter * (1 + encoders.scale_error_left)\n"
      << "  ticks_per_meter_right: "
      << format_double(sc.robot.ticks_per_meter * (1.0 + e.scale_error_right))
      << "  # robot.ticks_per_meter * (1 + encoders.scale_error_right)\n"
      << "  wheel_base: " << format_double(sc.robot.wheel_base * (1.0 + e.wheel_base_error))
      << "  # robot.wheel_base * (1 + encoders.wheel_base_error)\n"
      << "gyro:\n"
      << "  noise_density: " << format_double(g.noise_density) << "  # rad/s/sqrt(Hz)\n"
      << "  initial_bias: " << format_double(g.initial_bias) << "  # rad/s\n"
      << "  bias_walk: " << format_double(g.bias_walk) << "  # rad/s/sqrt(s)\n"
      << "  scale_error: " << format_double(g.scale_error) << "\n"
      << "camera:\n"
      << "  fx: " << format_double(c.fx) << "\n"
      << "  fy: " << format_double(c.fy) << "\n"
      << "  cx: " << format_double(c.cx) << "\n"
      << "  cy: " << format_double(c.cy) << "\n"
      << "  distortion: [" << format_double(c.distortion[0]) << ", "
      << format_double(c.distortion[1]) << ", " << format_double(c.distortion[2]) << ", "
      << format_double(c.distortion[3]) << "]\n";
  if (!out) {
    return readers::Status::failure(path + ": write error");
  }
  return {};
}

Pose3 body_to_camera(const Scenario::Camera& c) {
  const double t = c.tilt_deg * kDegToRad;
  const double ct = std::cos(t), st = std::sin(t);
  // Columns: camera x (right), y (down), z (forward, tilted up) in body coordinates.
  Mat3 r{{{{0.0, st, ct}, {-1.0, 0.0, 0.0}, {0.0, -ct, st}}}};
  return Pose3{r, Vec3{c.forward_m, 0.0, c.height_m}};
}

hal::Calibration calibration_of(const Scenario& sc) {
  hal::Calibration cal;
  const auto& c = sc.camera;
  cal.camera.width = c.width;
  cal.camera.height = c.height;
  cal.camera.fx = c.fx;
  cal.camera.fy = c.fy;
  cal.camera.cx = c.cx;
  cal.camera.cy = c.cy;
  cal.camera.distortion = c.distortion;
  const Pose3 bc = body_to_camera(c);
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      cal.camera.T_body_cam[4 * i + j] = bc.rotation.m[i][j];
    }
  }
  cal.camera.T_body_cam[3] = bc.position.x;
  cal.camera.T_body_cam[7] = bc.position.y;
  cal.camera.T_body_cam[11] = bc.position.z;
  cal.camera.T_body_cam[12] = cal.camera.T_body_cam[13] = cal.camera.T_body_cam[14] = 0.0;
  cal.camera.T_body_cam[15] = 1.0;
  cal.camera.pixel_noise = std::max(c.pixel_noise, 0.1);
  cal.camera.time_offset_s = 0.0;
  cal.wheels.ticks_per_meter_left = sc.robot.ticks_per_meter;
  cal.wheels.ticks_per_meter_right = sc.robot.ticks_per_meter;
  cal.wheels.wheel_base = sc.robot.wheel_base;
  cal.wheels.distance_noise = std::max(0.01, std::max(std::abs(sc.encoders.scale_error_left),
                                                      std::abs(sc.encoders.scale_error_right)) +
                                                 sc.encoders.distance_noise);
  cal.wheels.scale_error =
      std::max(std::abs(sc.encoders.scale_error_left), std::abs(sc.encoders.scale_error_right));
  cal.gyro.noise_density = std::max(sc.gyro.noise_density, 1e-6);
  // The filter reads bias_instability as the std. dev. of the bias it cannot estimate: the sim's
  // turn-on bias is never estimated (the robot starts moving), so it must be covered.
  cal.gyro.bias_instability = std::max({std::abs(sc.gyro.initial_bias), sc.gyro.bias_walk, 1e-6});
  cal.gyro.scale_error = std::abs(sc.gyro.scale_error);
  cal.gyro.bias_walk = sc.gyro.bias_walk;
  return cal;
}

bool project(const Scenario::Camera& c, Vec3 p, double& u, double& v) {
  if (p.z <= 1e-6) {
    return false;
  }
  const double x = p.x / p.z, y = p.y / p.z;
  const double r2 = x * x + y * y;
  const auto& d = c.distortion;
  const double radial = 1.0 + d[0] * r2 + d[1] * r2 * r2;
  const double xd = x * radial + 2.0 * d[2] * x * y + d[3] * (r2 + 2.0 * x * x);
  const double yd = y * radial + d[2] * (r2 + 2.0 * y * y) + 2.0 * d[3] * x * y;
  u = c.fx * xd + c.cx;
  v = c.fy * yd + c.cy;
  return true;
}

std::vector<Visible> visible_landmarks(const Scenario::Camera& c, const World& world,
                                       const std::vector<Landmark>& landmarks, const Pose3& wc) {
  std::vector<Visible> out;
  for (const Landmark& l : landmarks) {
    const Vec3 to_cam = wc.position - l.position;
    const double range = norm(to_cam);
    if (range < c.min_range || range > c.max_range) {
      continue;
    }
    if (norm(l.normal) > 0.0 && dot(l.normal, to_cam) < c.min_facing_cos * range) {
      continue;
    }
    const Vec3 pc = wc.apply_inverse(l.position);
    if (pc.z < 0.2 * range) {
      continue;  // far outside the field of view: distortion is invalid
    }
    double u = 0.0, v = 0.0;
    if (!project(c, pc, u, v)) {
      continue;
    }
    if (u < 0.0 || v < 0.0 || u > c.width - 1.0 || v > c.height - 1.0) {
      continue;
    }
    if (world.occluded(wc.position, l.position)) {
      continue;
    }
    out.push_back(Visible{&l, u, v, range});
  }
  return out;
}

readers::Result<SimulationSummary> simulate(const Scenario& sc, const std::string& out_dir,
                                            const std::function<void(double)>& progress) {
  using R = readers::Result<SimulationSummary>;
  Random world_rng(sc.world_seed(), stream::kWorld);
  Random path_rng(sc.seed, stream::kPath);
  const World world(sc, world_rng);
  const PathPlan plan = plan_path(sc, path_rng);
  const double true_wheel_base = sc.robot.wheel_base * (1.0 + sc.encoders.wheel_base_error);
  const Trajectory traj(plan.primitives, plan.start, true_wheel_base);
  const double duration = traj.duration();
  if (duration <= 0.0) {
    return R::failure(sc.name + ": the path is empty");
  }
  if (duration > 24.0 * 3600.0) {
    return R::failure(sc.name + ": the path takes " + std::to_string(std::lround(duration)) +
                      " s, more than a day: set duration_s, or a smaller world.size or path");
  }
  if (sc.duration_s > duration + 1e-6) {
    // A path that ends early would leave the dataset short without a word; it does not repeat
    // unless path.repeats says so.
    char end_s[32];
    std::snprintf(end_s, sizeof end_s, "%.1f", std::floor(duration * 10.0) / 10.0);
    std::string fix = std::string("set duration_s to at most ") + end_s;
    if (sc.path.type == "boustrophedon") {
      const double pass_s = duration / std::max(1, sc.path.repeats);
      fix += ", or path.repeats to " +
             std::to_string(static_cast<long>(std::ceil(sc.duration_s / pass_s))) +
             " (the lanes driven again, " + std::to_string(std::lround(pass_s)) + " s a pass)";
    }
    return R::failure(sc.name + ": duration_s " + std::to_string(std::lround(sc.duration_s)) +
                      " s is longer than the path, which ends at " + end_s + " s: " + fix);
  }

  DatasetWriter writer;
  readers::Status s =
      writer.open(out_dir, calibration_of(sc),
                  sc.camera.image_format == "pgm" ? DatasetWriter::ImageFormat::kPgm
                                                  : DatasetWriter::ImageFormat::kPng);
  if (!s) {
    return R::failure(s.error());
  }
  SimulationSummary sum;
  sum.duration_s = duration;
  sum.path_length_m = traj.length();
  sum.landmarks = static_cast<int>(world.landmarks().size());
  const double t0 = sc.start_time_s;
  auto report = [&](double f) {
    if (progress) {
      progress(f);
    }
  };

  // Ground truth.
  {
    const double dt = 1.0 / sc.groundtruth.rate_hz;
    for (long k = 0;; ++k) {
      const double t = static_cast<double>(k) * dt;
      if (t > duration) {
        break;
      }
      const TrueState st = traj.at(t);
      const Pose3 b = Trajectory::body_pose(st);
      writer.add_groundtruth(readers::GroundTruthPose{to_ns(t0 + t),
                                                      {st.position.x, st.position.y, st.position.z},
                                                      quaternion_wxyz(b.rotation)});
    }
  }
  // Wheel-drop state changes (lift.csv, a format extension).
  for (const auto& [lift_start, lift_end] : traj.lift_intervals()) {
    writer.add_lift(readers::LiftRow{to_ns(t0 + lift_start), true});
    writer.add_lift(readers::LiftRow{to_ns(t0 + lift_end), false});
  }
  report(0.1);
  // Gyro: (1 + scale) * mean true rate over the sample interval + bias (random walk) + white noise.
  {
    Random rng(sc.seed, stream::kGyro);
    const auto& g = sc.gyro;
    const double dt = 1.0 / g.rate_hz;
    const double white = g.noise_density * std::sqrt(g.rate_hz);
    double bias = g.initial_bias;
    double prev_yaw = traj.at(0.0).yaw;
    for (long k = 1;; ++k) {
      const double t = static_cast<double>(k) * dt;
      if (t > duration) {
        break;
      }
      const double yaw = traj.at(t).yaw;
      const double rate = (yaw - prev_yaw) / dt;
      prev_yaw = yaw;
      bias += rng.gaussian(g.bias_walk * std::sqrt(dt));
      hal::GyroSample sample;
      sample.t_ns = to_ns(t0 + t);
      sample.wz_rad_s = (1.0 + g.scale_error) * rate + bias + rng.gaussian(white);
      writer.add_gyro(sample);
      ++sum.gyro_samples;
    }
  }
  report(0.3);
  // Encoders: per-wheel scale error, relative noise, slips, quantization, 32-bit wrap.
  {
    Random rng(sc.seed, stream::kEncoders);
    const auto& e = sc.encoders;
    const double dt = 1.0 / e.rate_hz;
    const double phase = 0.003;
    double meas_l = 0.0, meas_r = 0.0;
    TrueState prev = traj.at(0.0);
    double slip_until = -1.0;
    int slip_wheel = 0;
    for (long k = 0;; ++k) {
      const double t = phase + static_cast<double>(k) * dt;
      if (t > duration) {
        break;
      }
      const TrueState st = traj.at(t);
      double dl = st.left_m - prev.left_m;
      double dr = st.right_m - prev.right_m;
      prev = st;
      if (e.slip_rate_hz > 0.0 && t > slip_until && rng.chance(e.slip_rate_hz * dt)) {
        slip_until = t + e.slip_duration_s;
        slip_wheel = static_cast<int>(rng.below(2));
        ++sum.slip_events;
      }
      const bool slipping = t <= slip_until;
      dl *= (1.0 + e.scale_error_left) * (1.0 + rng.gaussian(e.distance_noise));
      dr *= (1.0 + e.scale_error_right) * (1.0 + rng.gaussian(e.distance_noise));
      if (slipping && slip_wheel == 0) {
        dl *= 1.0 + e.slip_fraction;
      }
      if (slipping && slip_wheel == 1) {
        dr *= 1.0 + e.slip_fraction;
      }
      meas_l += dl;
      meas_r += dr;
      hal::EncoderSample sample;
      sample.t_ns = to_ns(t0 + t);
      sample.left_ticks =
          wrap32(sc.robot.initial_ticks +
                 static_cast<std::int64_t>(std::floor(meas_l * sc.robot.ticks_per_meter)));
      sample.right_ticks =
          wrap32(sc.robot.initial_ticks +
                 static_cast<std::int64_t>(std::floor(meas_r * sc.robot.ticks_per_meter)));
      writer.add_encoder(sample);
      ++sum.encoder_samples;
    }
  }
  report(0.5);
  // Camera (feature mode): landmarks in view at the true capture time, pixel noise, outliers;
  // the stamp carries jitter.
  {
    Random rng(sc.seed, stream::kCamera);
    Random image_rng(sc.seed, stream::kImage);
    const auto& c = sc.camera;
    const bool write_features = c.mode == "features" || c.mode == "both";
    const bool checkerboard = c.mode == "checkerboard";
    const bool write_images = c.mode == "images" || c.mode == "both" || checkerboard;
    std::unique_ptr<Renderer> renderer;
    if (write_images && !checkerboard) {
      renderer = std::make_unique<Renderer>(sc);
    }
    std::unique_ptr<CheckerboardRenderer> board_renderer;
    if (checkerboard) {
      board_renderer = std::make_unique<CheckerboardRenderer>(sc);
    }
    readers::GrayImage image;
    FrameExposure frame_exposure(c, body_to_camera(c));
    const double dt = 1.0 / c.rate_hz;
    const double phase = 0.013;
    const Pose3 bc = body_to_camera(c);
    hal::TimeNs last_stamp = std::numeric_limits<hal::TimeNs>::min();
    double total = 0.0;
    int good = 0;
    int enough = 0;
    double last_seen = 0.0;
    std::vector<hal::FeatureObservation> obs;
    std::vector<Landmark> all;
    for (long k = 0;; ++k) {
      const double t = phase + static_cast<double>(k) * dt;
      if (t > duration) {
        break;
      }
      const TrueState st = traj.at(t);
      const Pose3 wc = compose(Trajectory::body_pose(st), bc);
      all = world.landmarks();
      const auto person = world.person_points(t);
      all.insert(all.end(), person.begin(), person.end());
      auto vis = visible_landmarks(c, world, all, wc);
      std::sort(vis.begin(), vis.end(), [](const Visible& a, const Visible& b) {
        return a.range < b.range || (a.range == b.range && a.landmark->id < b.landmark->id);
      });
      if (vis.size() > static_cast<std::size_t>(std::max(0, c.max_features))) {
        vis.resize(static_cast<std::size_t>(std::max(0, c.max_features)));
      }
      std::sort(vis.begin(), vis.end(),
                [](const Visible& a, const Visible& b) { return a.landmark->id < b.landmark->id; });
      obs.clear();
      int static_in_view = 0;
      for (const Visible& vl : vis) {
        hal::FeatureObservation f;
        f.track_id = vl.landmark->id;
        if (c.outlier_probability > 0.0 && rng.chance(c.outlier_probability)) {
          f.u_px = rng.uniform(0.0, c.width - 1.0);
          f.v_px = rng.uniform(0.0, c.height - 1.0);
        } else {
          f.u_px = std::clamp(vl.u + rng.gaussian(c.pixel_noise), 0.0, c.width - 1.0);
          f.v_px = std::clamp(vl.v + rng.gaussian(c.pixel_noise), 0.0, c.height - 1.0);
        }
        obs.push_back(f);
        if (vl.landmark->id < kPersonTrackBase) {
          ++static_in_view;
        }
      }
      hal::TimeNs stamp = to_ns(t0 + t + (c.jitter_s > 0.0 ? rng.gaussian(c.jitter_s) : 0.0));
      stamp = std::max(stamp, last_stamp + 1);
      last_stamp = stamp;
      if (write_features) {
        writer.add_features(stamp, obs.data(), static_cast<int>(obs.size()));
      }
      if (write_images) {
        if (checkerboard) {
          const Pose3 board = sc.checkerboard.on_floor
                                  ? checkerboard_on_floor_pose(sc)
                                  : checkerboard_pose(sc, static_cast<int>(k), rng);
          board_renderer->render(board, image_rng, image);
        } else {
          frame_exposure.render(*renderer, traj, t, image_rng, image);
        }
        s = writer.add_image(stamp, image.view());
        if (!s) {
          return R::failure(s.error());
        }
      }
      ++sum.frames;
      if (obs.empty()) {
        ++sum.frames_without_features;
      }
      total += static_cast<double>(obs.size());
      if (static_in_view >= 5 && static_in_view <= 10) {
        ++good;
      }
      if (static_in_view >= 5) {
        ++enough;
      }
      if (static_in_view > 0) {
        sum.longest_gap_s = std::max(sum.longest_gap_s, t - last_seen);
        last_seen = t;
      }
      if (k % 64 == 0) {
        report(0.5 + 0.5 * t / duration);
      }
    }
    sum.longest_gap_s = std::max(sum.longest_gap_s, duration - last_seen);
    if (renderer) {
      sum.images = renderer->textures_note();
      if (c.auto_exposure) {
        char range[96];
        std::snprintf(range, sizeof range, "; auto-exposure gain %.2f..%.2f",
                      frame_exposure.min_gain(), frame_exposure.max_gain());
        sum.images += range;
      }
    }
    if (sum.frames > 0) {
      sum.mean_features = total / sum.frames;
      sum.fraction_frames_5_to_10 = static_cast<double>(good) / sum.frames;
      sum.fraction_frames_5_or_more = static_cast<double>(enough) / sum.frames;
    }
  }
  {
    std::ofstream lm(std::filesystem::path(out_dir) / "sim_landmarks.csv", std::ios::trunc);
    lm << "#id,x_m,y_m,z_m\n";
    for (const Landmark& l : world.landmarks()) {
      lm << l.id << ',' << readers::format_double(l.position.x) << ','
         << readers::format_double(l.position.y) << ',' << readers::format_double(l.position.z)
         << '\n';
    }
    if (!lm) {
      return R::failure(out_dir + "/sim_landmarks.csv: write error");
    }
  }
  s = write_sim_truth(sc, (std::filesystem::path(out_dir) / "sim_truth.yaml").string());
  if (!s) {
    return R::failure(s.error());
  }
  s = writer.close();
  if (!s) {
    return R::failure(s.error());
  }
  report(1.0);
  return sum;
}

}  // namespace cleanslam::sim_hal::sim
