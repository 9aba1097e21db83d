// cleanslam-replay DATASET --out DIR [--config FILE] [--set key=value ...]
// Runs the firmware's own loop on a dataset (readers' DatasetSource), as fast as it can, on a
// virtual clock: deterministic. Writes DIR/trajectory.tum (+ .cov), dead_reckoning.tum,
// landmarks.csv, diagnostics.csv, fusion.csv.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cleanslam/firmware/clocks.hpp"
#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/firmware/program.hpp"
#include "cleanslam/firmware/run.hpp"
#include "cleanslam/firmware/sinks.hpp"
#include "cleanslam/readers/dataset_source.hpp"

namespace {

using namespace cleanslam;

constexpr const char* kUsage =
    "usage: cleanslam-replay DATASET --out DIR [--config FILE] [--set key=value ...]\n"
    "Runs the firmware loop on a dataset folder as fast as possible (deterministic) and writes\n"
    "DIR/trajectory.tum (body pose at every processed frame, relative to the first, TUM\n"
    "t x y z qx qy qz qw), DIR/trajectory.tum.cov (t and the 6x6 covariance over x y z roll\n"
    "pitch yaw, row-major, position block in the frame of the first pose), "
    "DIR/dead_reckoning.tum,\n"
    "DIR/landmarks.csv (slot,x,y,z,sxx,sxy,sxz,syy,syz,szz), DIR/diagnostics.csv (one record per\n"
    "observation of a visual update) and DIR/fusion.csv (one per scalar update of an odometry\n"
    "measurement: the turns' difference with filter.wheel_drift_state).\n";

// A progress bar on stderr, driven by the published poses' time.
class Progress final : public hal::PoseSink {
 public:
  Progress(hal::TimeNs t0, hal::TimeNs t1) : t0_(t0), t1_(t1) {}
  void publish(const hal::PoseEstimate& p) override {
    const double f =
        t1_ > t0_ ? static_cast<double>(p.t_ns - t0_) / static_cast<double>(t1_ - t0_) : 1.0;
    const int percent = static_cast<int>(std::clamp(f, 0.0, 1.0) * 100.0);
    if (percent != last_) {
      last_ = percent;
      const int bars = percent / 2;
      std::fprintf(stderr, "\r[%.*s%*s] %3d%%", bars,
                   "##################################################", 50 - bars, "", percent);
    }
  }
  void flush() override {
    if (last_ >= 0) {
      std::fputc('\n', stderr);
    }
  }

 private:
  hal::TimeNs t0_;
  hal::TimeNs t1_;
  int last_ = -1;
};

int fail(const std::string& message) {
  std::fprintf(stderr, "cleanslam-replay: error: %s\n", message.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dataset;
  std::string out;
  std::string config_path;
  std::vector<std::string> sets;
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
  auto source = readers::DatasetSource::open(dataset);
  if (!source.ok()) {
    return fail(source.error());
  }
  for (const auto& w : source->warnings()) {
    std::fprintf(stderr, "cleanslam-replay: warning: %s\n", w.c_str());
  }
  if (config.calibration_from_dataset) {
    config.calibration = source->calibration();
  }
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) {
    return fail(out + ": cannot create: " + ec.message());
  }
  const std::unique_ptr<firmware::Estimator> estimator = firmware::make_estimator(config);
  firmware::Loop loop(config.loop, *estimator);
  loop.add_source(&source.value());
  std::string error;
  firmware::TumWriter trajectory;
  firmware::TumWriter dead_reckoning;
  firmware::DiagnosticsCsv diagnostics;
  firmware::FusionCsv fusion;
  if (!trajectory.open(out + "/trajectory.tum", true, true, error) ||
      !dead_reckoning.open(out + "/dead_reckoning.tum", true, false, error) ||
      !diagnostics.open(out + "/diagnostics.csv", error) ||
      !fusion.open(out + "/fusion.csv", error)) {
    return fail(error);
  }
  loop.add_frame_sinks(&trajectory, &dead_reckoning);
  loop.add_update_sink(&diagnostics);
  loop.add_update_sink(&fusion);
  const auto& ds = source->dataset();
  hal::TimeNs t0 = 0;
  hal::TimeNs t1 = 0;
  if (!ds.gyro.empty()) {
    t0 = ds.gyro.front().t_ns;
    t1 = ds.gyro.back().t_ns;
  }
  Progress progress(t0, t1);
  if (::isatty(STDERR_FILENO) != 0) {
    loop.add_pose_sink(&progress);
  }
  firmware::VirtualClock clock;
  firmware::StopSignals signals;
  const firmware::RunEnd end = firmware::run_virtual(loop, clock, false, &signals);
  trajectory.close();
  dead_reckoning.close();
  if (!firmware::write_landmarks_csv(*estimator, out + "/landmarks.csv", error)) {
    return fail(error);
  }
  firmware::print_summary(loop, stderr);
  if (source->image_errors() > 0) {
    std::fprintf(stderr, "cleanslam-replay: warning: %d images failed to load: %s\n",
                 source->image_errors(), source->last_error().c_str());
  }
  return end == firmware::RunEnd::kStopped ? 130 : 0;
}
