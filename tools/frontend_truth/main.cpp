// cleanslam-frontend-truth SCENARIO [--seed N] [--set key=value ...] [options]
//
// Measures the vision front end (Harris, patch scale prediction, Lucas-Kanade/NCC tracker)
// against the simulator's ground truth on rendered images, without the estimator: the scenario
// is rendered frame by frame as cleanslam-sim renders it; each tracked corner's true 3-D point is
// the ray cast through the pixel where it was detected, from the true camera pose; in later
// frames its true pixel is that point projected with the true pose. The tracker searches a region
// centred on the true pixel plus a simulated prediction error, and its result is compared with
// the true pixel. Prints the error distribution (median, 95th percentile, outlier fraction), the
// error against track age (drift) and the share of tracks on occlusion boundaries.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "cleanslam/readers/gray_image.hpp"
#include "cleanslam/sim_hal/sim/frame_exposure.hpp"
#include "cleanslam/sim_hal/sim/random.hpp"
#include "cleanslam/sim_hal/sim/renderer.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"
#include "cleanslam/sim_hal/sim/trajectory.hpp"
#include "cleanslam/sim_hal/sim/world.hpp"
#include "cleanslam/slam_core/frontend/harris.hpp"
#include "cleanslam/slam_core/frontend/patch.hpp"
#include "cleanslam/slam_core/frontend/search_region.hpp"
#include "cleanslam/slam_core/frontend/tracker.hpp"

namespace fe = cleanslam::slam_core::frontend;
namespace sim = cleanslam::sim_hal::sim;

namespace {

struct Options {
  std::string scenario;
  std::vector<std::string> overrides;
  int frames = 400;
  int tracks = 16;
  double pred_sigma_px = 2.0;  // simulated prediction error, 1 sigma per axis
  double gate_sigma_px = 4.0;  // search-region covariance sqrt(S) per axis
  double outlier_px = 3.0;
  std::string csv;
  // Replay mode: the dataset the scenario was simulated into and the replay's diagnostics.csv.
  std::string dataset;
  std::string diagnostics;
};

struct Track {
  sim::Vec3 point;
  fe::LandmarkPatch patch;
  bool boundary = false;
  int age = 0;
  int misses = 0;
};

struct Sample {
  double err = 0.0;
  double ex = 0.0;
  double ey = 0.0;
  int age = 0;
  bool boundary = false;
  float ncc = 0.0F;
};

void usage(std::FILE* to) {
  std::fprintf(to,
               "usage: cleanslam-frontend-truth SCENARIO [--seed N] [--set key=value ...]\n"
               "         [--frames N] [--tracks N] [--pred-sigma PX] [--gate-sigma PX]\n"
               "         [--outlier-px PX] [--csv FILE]\n"
               "  --frames N        camera frames to render (default 400)\n"
               "  --tracks N        tracks kept alive at once (default 16)\n"
               "  --pred-sigma PX   prediction error drawn per axis (default 2)\n"
               "  --gate-sigma PX   search-region sigma per axis (default 4)\n"
               "  --outlier-px PX   a match farther than this from the truth is an outlier (3)\n"
               "  --csv FILE        one row per search: frame,age,boundary,found,ncc,ex,ey\n"
               "  --dataset DS --diagnostics FILE\n"
               "                    instead: the errors of a replay's observations (its\n"
               "                    diagnostics.csv) of dataset DS, simulated from SCENARIO with\n"
               "                    the same seed and settings, by status (updated, rejected)\n");
}

bool parse_number(std::string_view flag, std::string_view text, double& out) {
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  if (ec != std::errc{} || ptr != text.data() + text.size() || !std::isfinite(out)) {
    std::fprintf(stderr, "cleanslam-frontend-truth: %.*s expects a number, got \"%.*s\"\n",
                 static_cast<int>(flag.size()), flag.data(), static_cast<int>(text.size()),
                 text.data());
    return false;
  }
  return true;
}

bool parse_args(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(stdout);
      std::exit(0);
    }
    if (a.starts_with("--")) {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "cleanslam-frontend-truth: %s needs a value\n", argv[i]);
        return false;
      }
      const std::string_view v = argv[++i];
      double x = 0.0;
      if (a == "--seed") {
        o.overrides.push_back("seed=" + std::string(v));
      } else if (a == "--set") {
        o.overrides.emplace_back(v);
      } else if (a == "--csv") {
        o.csv = v;
      } else if (a == "--dataset") {
        o.dataset = v;
      } else if (a == "--diagnostics") {
        o.diagnostics = v;
      } else if (!parse_number(a, v, x)) {
        return false;
      } else if (a == "--frames") {
        o.frames = static_cast<int>(x);
      } else if (a == "--tracks") {
        o.tracks = static_cast<int>(x);
      } else if (a == "--pred-sigma") {
        o.pred_sigma_px = x;
      } else if (a == "--gate-sigma") {
        o.gate_sigma_px = x;
      } else if (a == "--outlier-px") {
        o.outlier_px = x;
      } else {
        std::fprintf(stderr, "cleanslam-frontend-truth: unknown option %s\n", argv[i - 1]);
        return false;
      }
    } else if (o.scenario.empty()) {
      o.scenario = a;
    } else {
      std::fprintf(stderr, "cleanslam-frontend-truth: unexpected argument %s\n", argv[i]);
      return false;
    }
  }
  if (o.scenario.empty()) {
    usage(stderr);
    return false;
  }
  return true;
}

// Whether the 15x15 window around (u, v) sees more than one surface or a depth step of more than
// 10 %: the patch then straddles an occlusion boundary or a surface edge.
bool on_boundary(const sim::Renderer& r, const sim::Pose3& wc, double u, double v,
                 const sim::Renderer::SurfacePoint& centre) {
  for (int dy = -fe::kPatchRadius; dy <= fe::kPatchRadius; dy += 2) {
    for (int dx = -fe::kPatchRadius; dx <= fe::kPatchRadius; dx += 2) {
      const auto p = r.point_at(wc, u + dx, v + dy);
      if (p.surface != centre.surface ||
          std::abs(p.distance - centre.distance) > 0.1 * centre.distance) {
        return true;
      }
    }
  }
  return false;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) {
    return 0.0;
  }
  const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

void summarize(const char* label, const std::vector<Sample>& s, double outlier_px) {
  std::vector<double> err;
  std::vector<double> inl;
  int outliers = 0;
  for (const Sample& x : s) {
    err.push_back(x.err);
    if (x.err > outlier_px) {
      ++outliers;
    } else {
      inl.push_back(x.err);
    }
  }
  double rms_x = 0.0;
  double rms_y = 0.0;
  double mean_x = 0.0;
  double mean_y = 0.0;
  for (const Sample& x : s) {
    if (x.err <= outlier_px) {
      rms_x += x.ex * x.ex;
      rms_y += x.ey * x.ey;
      mean_x += x.ex;
      mean_y += x.ey;
    }
  }
  const double n_in = std::max<double>(1.0, static_cast<double>(inl.size()));
  std::printf(
      "%-22s n %5zu  median %.3f px  p95 %.3f px  outliers(>%.0f px) %5.2f %%  inlier rms x %.3f "
      "y %.3f  bias x %+.3f y %+.3f\n",
      label, s.size(), percentile(err, 0.5), percentile(err, 0.95), outlier_px,
      s.empty() ? 0.0 : 100.0 * outliers / static_cast<double>(s.size()), std::sqrt(rms_x / n_in),
      std::sqrt(rms_y / n_in), mean_x / n_in, mean_y / n_in);
}

// summarize() of the interior and the boundary samples separately.
void summarize_by_boundary(const char* interior, const char* boundary, const std::vector<Sample>& s,
                           double outlier_px) {
  std::vector<Sample> part;
  for (bool b : {false, true}) {
    part.clear();
    for (const Sample& x : s) {
      if (x.boundary == b) {
        part.push_back(x);
      }
    }
    summarize(b ? boundary : interior, part, outlier_px);
  }
}

// Frame stamps of the dataset in order (cam0/data.csv), so that a stamp gives the frame index
// and so the true capture time.
std::vector<long long> frame_stamps(const std::string& dataset) {
  std::vector<long long> out;
  std::ifstream in(dataset + "/cam0/data.csv");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      continue;
    }
    out.push_back(std::stoll(line.substr(0, line.find(','))));
  }
  return out;
}

struct Row {
  long long t_ns = 0;
  int slot = -1;
  std::string status;
  double u = 0.0;
  double v = 0.0;
};

std::vector<Row> read_diagnostics(const std::string& path) {
  std::vector<Row> out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      continue;
    }
    std::vector<std::string> f;
    std::size_t p = 0;
    while (true) {
      const std::size_t q = line.find(',', p);
      f.push_back(line.substr(p, q - p));
      if (q == std::string::npos) {
        break;
      }
      p = q + 1;
    }
    if (f.size() < 6) {
      continue;
    }
    out.push_back({std::stoll(f[0]), std::stoi(f[2]), f[3], std::stod(f[4]), std::stod(f[5])});
  }
  return out;
}

// Replay mode: every observation of the replay against the true projection of the point its
// landmark was initialized on.
int replay_errors(const Options& o, const sim::Scenario& sc, const sim::Trajectory& traj,
                  const sim::Renderer& renderer) {
  const auto stamps = frame_stamps(o.dataset);
  const auto rows = read_diagnostics(o.diagnostics);
  if (stamps.empty() || rows.empty()) {
    std::fprintf(stderr,
                 "cleanslam-frontend-truth: no frames in %s/cam0/data.csv or no rows in %s\n",
                 o.dataset.c_str(), o.diagnostics.c_str());
    return 1;
  }
  const auto& cam = sc.camera;
  const sim::Pose3 bc = sim::body_to_camera(cam);
  struct Truth {
    bool valid = false;
    sim::Vec3 point;
    bool boundary = false;
    int surface = -1;
    std::size_t born = 0;
  };
  std::vector<Truth> truth(4096);
  std::vector<Sample> updated;
  std::vector<Sample> gated;
  std::ofstream csv;
  if (!o.csv.empty()) {
    csv.open(o.csv);
    csv << "frame,slot,status,age,boundary,surface,u,v,ex,ey\n";
  }
  std::size_t k = 0;
  for (const Row& r : rows) {
    while (k + 1 < stamps.size() && stamps[k] < r.t_ns) {
      ++k;
    }
    if (stamps[k] != r.t_ns || r.slot < 0 || r.slot >= static_cast<int>(truth.size())) {
      continue;
    }
    const double t = 0.013 + static_cast<double>(k) / cam.rate_hz;
    const sim::Pose3 wc = sim::compose(sim::Trajectory::body_pose(traj.at(t)), bc);
    Truth& tr = truth[static_cast<std::size_t>(r.slot)];
    if (r.status == "initialized") {
      const auto hit = renderer.point_at(wc, r.u, r.v);
      tr.valid = hit.surface >= 0;
      tr.point = hit.point;
      tr.boundary = tr.valid && on_boundary(renderer, wc, r.u, r.v, hit);
      tr.born = k;
      tr.surface = hit.surface;
      continue;
    }
    if (!tr.valid || (r.status != "updated" && r.status != "gated")) {
      continue;
    }
    double u = 0.0;
    double v = 0.0;
    if (!sim::project(cam, wc.apply_inverse(tr.point), u, v)) {
      continue;
    }
    const Sample s{std::hypot(r.u - u, r.v - v),  r.u - u,     r.v - v,
                   static_cast<int>(k - tr.born), tr.boundary, 0.0F};
    (r.status == "updated" ? updated : gated).push_back(s);
    if (csv.is_open()) {
      csv << k << ',' << r.slot << ',' << r.status << ',' << s.age << ',' << (s.boundary ? 1 : 0)
          << ',' << tr.surface << ',' << r.u << ',' << r.v << ',' << s.ex << ',' << s.ey << '\n';
    }
  }
  summarize("updated (inliers)", updated, o.outlier_px);
  summarize("gated (JCBB outliers)", gated, o.outlier_px);
  summarize_by_boundary("updated, interior", "updated, boundary", updated, o.outlier_px);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse_args(argc, argv, o)) {
    return 2;
  }
  o.overrides.emplace_back("camera.mode=images");
  auto loaded = sim::load_scenario(o.scenario, o.overrides);
  if (!loaded) {
    std::fprintf(stderr, "cleanslam-frontend-truth: %s\n", loaded.error().c_str());
    return 1;
  }
  const sim::Scenario& sc = loaded.value();
  const auto& cam = sc.camera;
  sim::Random world_rng(sc.world_seed(), sim::stream::kWorld);
  sim::Random path_rng(sc.seed, sim::stream::kPath);
  const sim::World world(sc, world_rng);
  const sim::PathPlan plan = sim::plan_path(sc, path_rng);
  const sim::Trajectory traj(plan.primitives, plan.start,
                             sc.robot.wheel_base * (1.0 + sc.encoders.wheel_base_error));
  sim::Renderer renderer(sc);
  if (!o.dataset.empty() || !o.diagnostics.empty()) {
    return replay_errors(o, sc, traj, renderer);
  }
  sim::Random image_rng(sc.seed, sim::stream::kImage);
  sim::Random pred_rng(sc.seed, 99);
  const sim::Pose3 bc = sim::body_to_camera(cam);

  fe::HarrisDetector harris;
  const fe::Tracker tracker;
  std::vector<Track> tracks;
  std::vector<Sample> samples;
  int searches = 0;
  int misses = 0;
  int invalid_templates = 0;
  int spawned = 0;
  int spawned_boundary = 0;
  int occluded_lost = 0;
  std::ofstream csv;
  if (!o.csv.empty()) {
    csv.open(o.csv);
    csv << "frame,age,boundary,found,ncc,ex,ey\n";
  }

  cleanslam::readers::GrayImage image;
  sim::FrameExposure frame_exposure(cam, bc);
  const double dt = 1.0 / cam.rate_hz;
  for (int k = 0; k < o.frames; ++k) {
    const double t = 0.013 + static_cast<double>(k) * dt;
    if (t > traj.duration()) {
      break;
    }
    const sim::Pose3 wc = sim::compose(sim::Trajectory::body_pose(traj.at(t)), bc);
    frame_exposure.render(renderer, traj, t, image_rng, image);
    const auto view = image.view();
    harris.detect(view, cam.width, cam.height);

    // Track the live ones.
    std::vector<Track> kept;
    std::vector<std::pair<double, double>> occupied;
    for (Track& tr : tracks) {
      const sim::Vec3 pc = wc.apply_inverse(tr.point);
      double u = 0.0;
      double v = 0.0;
      const double margin = fe::kPatchRadius + 2;
      if (!sim::project(cam, pc, u, v) || u < margin || v < margin || u > cam.width - 1 - margin ||
          v > cam.height - 1 - margin) {
        continue;
      }
      const auto seen = renderer.point_at(wc, u, v);
      if (std::abs(seen.distance - sim::norm(tr.point - wc.position)) > 0.02) {
        ++occluded_lost;
        continue;
      }
      ++tr.age;
      fe::PatchTemplate tmpl;
      if (!fe::make_template(tr.patch, fe::predicted_patch_scale(tr.patch.first_depth_m, pc.z),
                             tracker.config().min_template_std, tmpl)) {
        ++invalid_templates;
        continue;
      }
      fe::PixelPrediction pred;
      pred.uv = {u + pred_rng.gaussian(o.pred_sigma_px), v + pred_rng.gaussian(o.pred_sigma_px)};
      pred.S = Eigen::Matrix2d::Identity() * (o.gate_sigma_px * o.gate_sigma_px);
      pred.depth_m = pc.z;
      pred.in_front = true;
      const fe::SearchRegion region = fe::make_search_region(pred, cam.width, cam.height);
      const fe::TrackResult r =
          tracker.track(view, tmpl, region, harris.corners(), harris.corner_count());
      ++searches;
      const double ex = r.u_px - u;
      const double ey = r.v_px - v;
      if (csv.is_open()) {
        csv << k << ',' << tr.age << ',' << (tr.boundary ? 1 : 0) << ',' << (r.found ? 1 : 0) << ','
            << r.ncc << ',' << ex << ',' << ey << '\n';
      }
      if (!r.found) {
        ++misses;
        if (++tr.misses >= 3) {
          continue;
        }
      } else {
        tr.misses = 0;
        samples.push_back({std::hypot(ex, ey), ex, ey, tr.age, tr.boundary, r.ncc});
      }
      occupied.emplace_back(u, v);
      kept.push_back(tr);
    }
    tracks = std::move(kept);

    // New tracks at the strongest corners away from the live ones.
    for (int i = 0; i < harris.corner_count() && static_cast<int>(tracks.size()) < o.tracks; ++i) {
      const fe::Corner& c = harris.corners()[i];
      bool free = true;
      for (const auto& [ou, ov] : occupied) {
        free = free && std::hypot(ou - c.x, ov - c.y) > 20.0;
      }
      if (!free) {
        continue;
      }
      const auto hit = renderer.point_at(wc, c.x, c.y);
      if (hit.surface < 0) {
        continue;
      }
      Track tr;
      const double depth = wc.apply_inverse(hit.point).z;
      if (!fe::capture_patch(view, c.x, c.y, depth, tr.patch)) {
        continue;
      }
      tr.point = hit.point;
      tr.boundary = on_boundary(renderer, wc, c.x, c.y, hit);
      ++spawned;
      spawned_boundary += tr.boundary ? 1 : 0;
      occupied.emplace_back(c.x, c.y);
      tracks.push_back(tr);
    }
  }

  std::printf(
      "%s seed %llu: searches %d, found %zu, missed %d (%.1f %%), no template %d, "
      "occluded %d\n",
      sc.name.c_str(), static_cast<unsigned long long>(sc.seed), searches, samples.size(), misses,
      searches > 0 ? 100.0 * misses / searches : 0.0, invalid_templates, occluded_lost);
  std::printf("tracks started %d, on an occlusion boundary or surface edge %d (%.1f %%)\n", spawned,
              spawned_boundary, spawned > 0 ? 100.0 * spawned_boundary / spawned : 0.0);
  summarize("all", samples, o.outlier_px);
  summarize_by_boundary("interior", "boundary", samples, o.outlier_px);
  std::vector<Sample> part;
  const int bins[][2] = {{1, 1}, {2, 3}, {4, 7}, {8, 15}, {16, 1000000}};
  for (const auto& bin : bins) {
    part.clear();
    for (const Sample& s : samples) {
      if (s.age >= bin[0] && s.age <= bin[1]) {
        part.push_back(s);
      }
    }
    char label[32];
    std::snprintf(label, sizeof label, "age %d..%d", bin[0], std::min(bin[1], 999));
    summarize(label, part, o.outlier_px);
  }
  return 0;
}
