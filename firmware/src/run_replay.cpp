#include <cstdio>
#include <memory>
#include <string>

#include "cleanslam/firmware/clocks.hpp"
#include "cleanslam/firmware/output_report.hpp"
#include "cleanslam/firmware/program.hpp"
#include "cleanslam/firmware/recorder.hpp"
#include "cleanslam/firmware/replay_check.hpp"
#include "cleanslam/firmware/run.hpp"
#include "log_reports.hpp"
#include "program_runs.hpp"

namespace cleanslam::firmware {

int run_replay(const Args& args) {
  readers::LogReader original;
  if (!original.open(args.replay_log)) {
    std::fprintf(stderr, "cleanslam: error: %s\n", original.error().c_str());
    return 2;
  }
  if (!original.has_config()) {
    std::fprintf(stderr, "cleanslam: error: %s: no configuration record: cannot replay\n",
                 args.replay_log.c_str());
    return 2;
  }
  if (!config_hash_checked(original, true) || !replayable_alone(original, args.replay_log)) {
    return 2;
  }
  if (!args.sets.empty() || !args.config_path.empty()) {
    std::fprintf(stderr,
                 "cleanslam: warning: --replay uses the log's recorded configuration; --config and "
                 "--set are ignored\n");
  }
  const ConfigResult cfg =
      parse_config(std::string(original.config_text()), args.replay_log + ":config", {});
  print_messages(cfg);
  if (!cfg.ok()) {
    return 2;
  }
  if (cfg.config.recorder.frame_every != 1) {
    std::fprintf(stderr,
                 "cleanslam: warning: the log kept every %d-th frame only: outputs cannot be "
                 "reproduced\n",
                 cfg.config.recorder.frame_every);
  }
  report_log_defects(original, nullptr);
  const std::unique_ptr<Estimator> estimator = make_estimator(cfg.config);
  Loop loop(loop_options(cfg.config), *estimator);
  readers::LogSource source(original, readers::LogSource::Pacing::kRecordedTicks,
                            cfg.config.loop.max_span_ns);
  loop.add_source(&source);
  Recorder recorder;
  RecorderOptions ro = cfg.config.recorder;
  ro.path = args.replay_out.empty() ? args.replay_log + ".replay" : args.replay_out;
  ro.max_file_bytes = std::size_t{1} << 40;  // one file, whatever the original's rotation
  ro.frame_every = 1;
  std::string error;
  if (!recorder.open(ro, original.config_text(), error)) {
    std::fprintf(stderr, "cleanslam: error: %s\n", error.c_str());
    return 2;
  }
  loop.set_recorder(&recorder);
  VirtualClock clock;
  StopSignals signals;
  run_recorded(loop, clock, source, &signals);
  recorder.close();
  report_log_source(source, args.replay_log, nullptr);
  if (!close_and_report_outputs("cleanslam", nullptr, nullptr, &recorder, stderr)) {
    return 2;
  }
  readers::LogReader replayed;
  if (!replayed.open(ro.path)) {
    std::fprintf(stderr, "cleanslam: error: %s\n", replayed.error().c_str());
    return 2;
  }
  const bool truncated = original.defects(readers::LogDefect::kTruncated) > 0;
  const OutputComparison c = compare_outputs(original, replayed, truncated);
  if (c.identical) {
    std::fprintf(stderr, "cleanslam: replay of %s: %zu output records reproduced bit for bit%s\n",
                 args.replay_log.c_str(), c.original_outputs,
                 truncated ? " (up to the truncation)" : "");
    return 0;
  }
  std::fprintf(stderr, "cleanslam: replay of %s differs: %s\n", args.replay_log.c_str(),
               c.description.c_str());
  return 1;
}

}  // namespace cleanslam::firmware
