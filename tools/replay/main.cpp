// cleanslam-replay DATASET --out DIR [--force] [--accept-gaps] [--config FILE] [--set key=value]
// Runs the firmware's own loop on a dataset through the readers library, as fast as it can, on a
// virtual clock: deterministic. Writes DIR/trajectory.tum (+ .cov), dead_reckoning.tum,
// dead_reckoning_published.tum, landmarks.csv, diagnostics.csv.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cleanslam/firmware/clocks.hpp"
#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/health_report.hpp"
#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/firmware/map_store.hpp"
#include "cleanslam/firmware/output_report.hpp"
#include "cleanslam/firmware/program.hpp"
#include "cleanslam/firmware/run.hpp"
#include "cleanslam/firmware/run_report.hpp"
#include "cleanslam/firmware/sinks.hpp"
#include "cleanslam/readers/dataset_source.hpp"
#include "cleanslam/tools/output_paths.hpp"

namespace {

using namespace cleanslam;

constexpr const char* kUsage =
    "usage: cleanslam-replay DATASET --out DIR [--force] [--accept-gaps] [--config FILE]\n"
    "                        [--set key=value ...]\n"
    "Runs the firmware loop on a dataset folder as fast as possible (deterministic) and writes\n"
    "into DIR (created; refused when it holds anything, unless --force, and never inside\n"
    "DATASET):\n"
    "  trajectory.tum      body pose at every processed frame, relative to the first (TUM:\n"
    "                      t x y z qx qy qz qw)\n"
    "  trajectory.tum.cov  t and the 6x6 covariance over x y z roll pitch yaw, row-major,\n"
    "                      position block in the frame of the first pose\n"
    "  dead_reckoning.tum  wheels and gyro alone, at the same frames\n"
    "  dead_reckoning_published.tum  the same at every published pose (loop.publish_rate_hz):\n"
    "                      the same time stamps whatever the camera mode\n"
    "  landmarks.csv       slot,x,y,z,sxx,sxy,sxz,syy,syz,szz\n"
    "  diagnostics.csv     one record per observation of a visual update\n"
    "With --set map.path=FILE the map is checked at start and saved there every\n"
    "map.save_interval_s and at the end (docs/architecture.md, \"Map file\").\n"
    "--force        replace the outputs of an earlier run in DIR\n"
    "--accept-gaps  exit 0 even when a sensor falls silent for longer than its timeout\n"
    "               (loop.gyro_timeout_s, encoder_timeout_s, camera_timeout_s) or ends early\n"
    "               (a feature-level dataset's camera silences are the scene's: only noted)\n"
    "Progress and the firmware's health report go to stderr: a bar on a terminal, else a line\n"
    "every 10 %. Exit status: 0 done, 1 a sensor gap (outputs written), 2 bad arguments,\n"
    "configuration or dataset, or the map not saved, 130 stopped by a signal.\n";

constexpr std::array<const char*, 6> kOutputs{"trajectory.tum",     "trajectory.tum.cov",
                                              "dead_reckoning.tum", "dead_reckoning_published.tum",
                                              "landmarks.csv",      "diagnostics.csv"};

// Progress on stderr, driven by the published poses' time: a bar on a terminal, else a line at
// every tenth.
class Progress final : public hal::PoseSink {
 public:
  Progress(hal::TimeNs t0, hal::TimeNs t1, bool tty) : t0_(t0), t1_(t1), tty_(tty) {}
  void publish(const hal::PoseEstimate& p) override {
    const double f =
        t1_ > t0_ ? static_cast<double>(p.t_ns - t0_) / static_cast<double>(t1_ - t0_) : 1.0;
    show(static_cast<int>(std::clamp(f, 0.0, 1.0) * 100.0));
  }
  void flush() override {}
  void done() {
    show(100);
    if (tty_) {
      std::fputc('\n', stderr);
    }
  }

 private:
  void show(int percent) {
    if (percent == last_ || (!tty_ && percent / 10 == last_ / 10 && last_ >= 0)) {
      return;
    }
    last_ = percent;
    if (tty_) {
      const int bars = percent / 2;
      std::fprintf(stderr, "\r[%.*s%*s] %3d%%", bars,
                   "##################################################", 50 - bars, "", percent);
    } else {
      std::fprintf(stderr, "cleanslam-replay: %3d %% (t=%.1f s of %.1f s)\n", percent / 10 * 10,
                   hal::to_seconds(t1_ - t0_) * (percent / 10 * 10) / 100.0,
                   hal::to_seconds(t1_ - t0_));
    }
    std::fflush(stderr);
  }

  hal::TimeNs t0_;
  hal::TimeNs t1_;
  bool tty_;
  int last_ = -1;
};

// The dead-reckoning pose at every published pose's time.
class DeadReckoningAtPublish final : public hal::PoseSink {
 public:
  DeadReckoningAtPublish(const firmware::Estimator& estimator, hal::PoseSink& sink)
      : estimator_(estimator), sink_(sink) {}
  void publish(const hal::PoseEstimate& p) override {
    sink_.publish(estimator_.dead_reckoning_pose(p.t_ns));
  }
  void flush() override { sink_.flush(); }

 private:
  const firmware::Estimator& estimator_;
  hal::PoseSink& sink_;
};

int fail(const std::string& message) {
  std::fprintf(stderr, "cleanslam-replay: error: %s\n", message.c_str());
  return 2;
}

// The file behind each silent source, for the error message.
std::string source_file(const readers::DatasetSummary& ds, firmware::HealthReport::Source s) {
  switch (s) {
    case firmware::HealthReport::kGyro:
      return ds.folder + "/gyro.csv";
    case firmware::HealthReport::kEncoders:
      return ds.folder + "/encoders.csv";
    default:
      return ds.folder + (ds.has_camera ? "/cam0/data.csv" : "/features.csv");
  }
}

hal::TimeNs timeout_of(const firmware::LoopOptions& o, firmware::HealthReport::Source s) {
  switch (s) {
    case firmware::HealthReport::kGyro:
      return o.gyro_timeout_ns;
    case firmware::HealthReport::kEncoders:
      return o.encoder_timeout_ns;
    default:
      return o.camera_timeout_ns;
  }
}

const char* timeout_key(firmware::HealthReport::Source s) {
  switch (s) {
    case firmware::HealthReport::kGyro:
      return "loop.gyro_timeout_s";
    case firmware::HealthReport::kEncoders:
      return "loop.encoder_timeout_s";
    default:
      return "loop.camera_timeout_s";
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string dataset;
  std::string out;
  std::string config_path;
  std::vector<std::string> sets;
  bool force = false;
  bool accept_gaps = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--help" || a == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if ((a == "--out" || a == "--config" || a == "--set") && !has_value) {
      return fail(a + " needs a value");
    }
    if (a == "--out") {
      out = argv[++i];
    } else if (a == "--config") {
      config_path = argv[++i];
    } else if (a == "--set") {
      sets.emplace_back(argv[++i]);
    } else if (a == "--force") {
      force = true;
    } else if (a == "--accept-gaps") {
      accept_gaps = true;
    } else if (!a.empty() && a[0] != '-' && dataset.empty()) {
      dataset = a;
    } else {
      std::fputs(kUsage, stderr);
      return fail("unexpected argument " + a);
    }
  }
  if (dataset.empty() || out.empty()) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  sets.emplace_back("source.kind=dataset");
  sets.emplace_back("source.path=\"" + dataset + "\"");
  const firmware::ConfigResult cfg = firmware::load_config(config_path, sets);
  for (const auto& w : cfg.warnings) {
    std::fprintf(stderr, "cleanslam-replay: warning: %s\n", w.c_str());
  }
  if (!cfg.ok()) {
    for (const auto& e : cfg.errors) {
      std::fprintf(stderr, "cleanslam-replay: error: %s\n", e.c_str());
    }
    return 2;
  }
  firmware::FirmwareConfig config = cfg.config;
  readers::DatasetSource::Options source_options;
  source_options.load.max_span_ns = config.loop.max_span_ns;
  auto source = readers::DatasetSource::open(dataset, source_options);
  if (!source.ok()) {
    return fail(source.error());
  }
  for (const auto& w : source->warnings()) {
    std::fprintf(stderr, "cleanslam-replay: warning: %s\n", w.c_str());
  }
  if (config.calibration_from_dataset) {
    config.calibration = source->calibration();
  }
  // The map first: a second process on the same map is refused before it writes any output.
  firmware::RunMap map(config.map, "cleanslam-replay");
  if (map.refused()) {
    return 2;
  }
  const tools::OwnedEntry ours = [](const std::string& name) {
    return std::find(kOutputs.begin(), kOutputs.end(), name) != kOutputs.end();
  };
  if (const readers::Status s = tools::prepare_output_dir(out, force, ours, {dataset}); !s) {
    return fail(s.error());
  }
  const std::unique_ptr<firmware::Estimator> estimator = firmware::make_estimator(config);
  firmware::Loop loop(firmware::loop_options(config), *estimator);
  loop.add_source(&source.value());
  std::string error;
  firmware::TumWriter trajectory;
  firmware::TumWriter dead_reckoning;
  firmware::TumWriter dead_reckoning_published;
  firmware::DiagnosticsCsv diagnostics;
  if (!trajectory.open(out + "/trajectory.tum", true, true, error) ||
      !dead_reckoning.open(out + "/dead_reckoning.tum", true, false, error) ||
      !dead_reckoning_published.open(out + "/dead_reckoning_published.tum", true, false, error) ||
      !diagnostics.open(out + "/diagnostics.csv", error)) {
    return fail(error);
  }
  loop.add_frame_sinks(&trajectory, &dead_reckoning);
  DeadReckoningAtPublish published(*estimator, dead_reckoning_published);
  loop.add_pose_sink(&published);
  loop.add_update_sink(&diagnostics);
  firmware::CameraOffsetEstimate camera_offset(config.calibration.camera);
  loop.add_update_sink(&camera_offset);
  loop.add_gyro_sink(&camera_offset);
  const readers::DatasetSummary& ds = source->summary();
  const hal::TimeNs t0 = ds.first_ns;
  const hal::TimeNs t1 = ds.last_ns;
  Progress progress(t0, t1, ::isatty(STDERR_FILENO) != 0);
  loop.add_pose_sink(&progress);
  firmware::HealthReport health("cleanslam-replay", stderr);
  loop.set_health_observer(&health);
  firmware::VirtualClock clock;
  firmware::StopSignals signals;
  const firmware::RunEnd end = firmware::run_virtual(loop, clock, false, &signals, map.task());
  health.finish(clock.now());
  const bool map_saved = map.finish(*estimator, clock.now());
  bool outputs_written = firmware::close_and_report_outputs("cleanslam-replay", &trajectory,
                                                            &diagnostics, nullptr, stderr);
  outputs_written = firmware::close_and_report_outputs("cleanslam-replay", &dead_reckoning, nullptr,
                                                       nullptr, stderr) &&
                    outputs_written;
  outputs_written = firmware::close_and_report_outputs(
                        "cleanslam-replay", &dead_reckoning_published, nullptr, nullptr, stderr) &&
                    outputs_written;
  if (end != firmware::RunEnd::kStopped) {
    progress.done();
  }
  if (!firmware::write_landmarks_csv(*estimator, out + "/landmarks.csv", error)) {
    return fail(error);
  }
  firmware::print_summary(loop, camera_offset, stderr);
  if (source->image_errors() > 0) {
    std::fprintf(stderr, "cleanslam-replay: warning: %d images failed to load: %s\n",
                 source->image_errors(), source->last_error().c_str());
  }
  if (!source->stream_error().empty()) {
    return fail(source->stream_error());
  }
  if (!map_saved || !outputs_written) {
    return 2;
  }
  if (end == firmware::RunEnd::kStopped) {
    std::fprintf(stderr,
                 "cleanslam-replay: stopped by a signal at t=%.1f s of %.1f s: outputs in %s are "
                 "partial\n",
                 hal::to_seconds(std::max(clock.now(), t0) - t0), hal::to_seconds(t1 - t0),
                 out.c_str());
    return 130;
  }
  std::fprintf(stderr, "cleanslam-replay: outputs in %s\n", out.c_str());
  bool gaps = false;
  for (int i = 0; i < firmware::HealthReport::kSourceCount; ++i) {
    const auto src = static_cast<firmware::HealthReport::Source>(i);
    const firmware::HealthReport::Silence& g = health.silence(src);
    // One silence that lasted less than its timeout once raised: a stream that ended a moment
    // before the others, or a harmless stutter, not a gap.
    if (g.episodes == 0 || (g.episodes == 1 && g.total_ns < timeout_of(config.loop, src))) {
      continue;
    }
    // features.csv has no row for a frame without features: its silences are the scene's (no
    // landmark in view), not the recording's.
    const bool scene = src == firmware::HealthReport::kCamera && !ds.has_camera;
    gaps = gaps || !scene;
    std::fprintf(stderr,
                 "cleanslam-replay: %s: %s: %s silent %d time(s) for longer than %s = %.3g s, "
                 "first at t=%.3f s, %.1f s in all (of %.1f s)%s\n",
                 scene ? "note" : (accept_gaps ? "warning" : "error"), source_file(ds, src).c_str(),
                 firmware::HealthReport::source_name(src), g.episodes, timeout_key(src),
                 hal::to_seconds(timeout_of(config.loop, src)), hal::to_seconds(g.first_ns),
                 hal::to_seconds(g.total_ns), hal::to_seconds(t1 - t0),
                 scene ? ": frames without features (no landmark in view)" : "");
  }
  if (gaps && !accept_gaps) {
    std::fputs(
        "cleanslam-replay: the dataset has sensor gaps (a file cut short or samples missing): "
        "the outputs are written but do not measure the estimator; --accept-gaps accepts them\n",
        stderr);
    return 1;
  }
  return 0;
}
