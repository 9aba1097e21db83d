#include <cstdio>
#include <optional>

#include "cleanslam/firmware/clocks.hpp"
#include "cleanslam/firmware/map_store.hpp"
#include "cleanslam/firmware/output_report.hpp"
#include "cleanslam/firmware/program.hpp"
#include "cleanslam/firmware/robot_calibration.hpp"
#include "cleanslam/firmware/run.hpp"
#include "cleanslam/firmware/run_report.hpp"
#include "cleanslam/firmware/status_indicator.hpp"
#include "log_reports.hpp"
#include "output_wiring.hpp"
#include "program_runs.hpp"
#include "source_setup.hpp"

namespace cleanslam::firmware {

int run_normal(const Args& args) {
  ConfigResult cfg = load_config(args.config_path, args.sets);
  print_messages(cfg);
  if (!cfg.ok()) {
    return 2;
  }
  FirmwareConfig config = cfg.config;
  RunSources sources;
  if (!open_sources(args, cfg, config, sources)) {
    return 2;
  }
  const std::unique_ptr<Estimator> estimator = make_estimator(config);
  // The map first: a second process on the same map is refused before it writes any output.
  RunMap map(config.map, "cleanslam");
  if (map.refused()) {
    return 2;
  }
  Loop loop(loop_options(config), *estimator);
  sources.add_to(loop);
  if (sources.log) {
    report_log_defects(*sources.log, &loop);
  }
  RunOutputs outputs(config.calibration.camera);
  if (!wire_outputs(config, sources.robot != nullptr, loop, outputs)) {
    return 2;
  }
  LiveTask* saving = map.task();
  StopSignals signals;
  RunEnd end = RunEnd::kStopped;
  hal::TimeNs end_ns = 0;
  if (drivers::RobotDrivers* robot = sources.robot.get()) {
    MonotonicClock clock;
    std::optional<StatusIndicator> indicator;
    if (robot->status_led() != nullptr) {
      indicator.emplace(*robot->status_led(), robot->inputs_missing() || sources.uncalibrated);
    }
    TaskPair tasks(indicator ? &*indicator : nullptr, saving);
    end = run_live(loop, clock, signals, &tasks);
    end_ns = clock.now();
  } else {
    VirtualClock clock;
    end = run_virtual(loop, clock, config.source.realtime, &signals, saving);
    end_ns = clock.now();
  }
  outputs.recorder.close();
  const bool outputs_written = close_and_report_outputs(
      "cleanslam", &outputs.tum, &outputs.diagnostics, &outputs.recorder, stderr);
  const bool map_saved = map.finish(*estimator, end_ns);
  report_sources(sources, config, loop);
  print_summary(loop, outputs.camera_offset, stderr);
  if (sources.uncalibrated) {
    std::fprintf(stderr, "cleanslam: warning: %s\n",
                 uncalibrated_message(cfg.calibration_not_set, args.config_path).c_str());
  }
  if (end == RunEnd::kStopped) {
    std::fprintf(stderr, "cleanslam: stopped by signal, outputs flushed\n");
  }
  if (sources.dataset != nullptr && !sources.dataset->stream_error().empty()) {
    std::fprintf(stderr, "cleanslam: error: %s\n", sources.dataset->stream_error().c_str());
    return 2;
  }
  return map_saved && outputs_written ? 0 : 2;
}

}  // namespace cleanslam::firmware
