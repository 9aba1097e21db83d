#include "cleanslam/firmware/program.hpp"

#include <array>
#include <cstring>
#include <filesystem>
#include <optional>

#include "cleanslam/drivers/robot_drivers.hpp"
#include "cleanslam/firmware/clocks.hpp"
#include "cleanslam/firmware/health_report.hpp"
#include "cleanslam/firmware/map_store.hpp"
#include "cleanslam/firmware/output_report.hpp"
#include "cleanslam/firmware/recorder.hpp"
#include "cleanslam/firmware/replay_check.hpp"
#include "cleanslam/firmware/robot_calibration.hpp"
#include "cleanslam/firmware/run.hpp"
#include "cleanslam/firmware/sinks.hpp"
#include "cleanslam/firmware/status_indicator.hpp"
#include "cleanslam/firmware/summary_words.hpp"
#include "cleanslam/firmware/systemd_notifier.hpp"
#include "cleanslam/readers/dataset_source.hpp"
#include "cleanslam/readers/log_source.hpp"

namespace cleanslam::firmware {

namespace {

constexpr const char* kUsage =
    "usage: cleanslam [--config FILE] [--set key=value ...]\n"
    "                 [--dataset DIR | --log LOG] [--realtime] [--record LOG] [--tum FILE]\n"
    "       cleanslam --replay LOG [--replay-out FILE]\n"
    "       cleanslam --print-sample-config | --version | --help\n"
    "Runs the localization loop on the robot's drivers, a dataset folder or a recorded log.\n"
    "--replay feeds a recorded log back through the loop at its recorded iterations and checks\n"
    "that the outputs are reproduced bit for bit (exit 0), else names the first difference\n"
    "(exit 1). --dataset/--log/--realtime/--record/--tum are shorthands for --set source.kind=,\n"
    "source.path=, source.realtime=true, recorder.path=, sinks.tum=.\n"
    "--print-sample-config prints every key with its default, range and meaning\n"
    "(firmware/config/cleanslam.sample.yaml).\n";

struct Args {
  std::string config_path;
  std::vector<std::string> sets;
  std::string replay_log;
  std::string replay_out;
  bool help = false;
  bool version = false;
  bool print_sample_config = false;
};

std::optional<Args> parse_args(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&](const char* name) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "cleanslam: %s needs a value\n", name);
        return nullptr;
      }
      return argv[++i];
    };
    const char* v = nullptr;
    if (arg == "--help" || arg == "-h") {
      a.help = true;
    } else if (arg == "--version") {
      a.version = true;
    } else if (arg == "--print-sample-config") {
      a.print_sample_config = true;
    } else if (arg == "--realtime") {
      a.sets.emplace_back("source.realtime=true");
    } else if (arg == "--config" || arg == "--set" || arg == "--replay" || arg == "--replay-out" ||
               arg == "--dataset" || arg == "--log" || arg == "--record" || arg == "--tum") {
      if ((v = value(arg.c_str())) == nullptr) {
        return std::nullopt;
      }
      if (arg == "--config") {
        a.config_path = v;
      } else if (arg == "--set") {
        a.sets.emplace_back(v);
      } else if (arg == "--replay") {
        a.replay_log = v;
      } else if (arg == "--replay-out") {
        a.replay_out = v;
      } else if (arg == "--dataset") {
        a.sets.emplace_back("source.kind=dataset");
        a.sets.emplace_back(std::string("source.path=\"") + v + "\"");
      } else if (arg == "--log") {
        a.sets.emplace_back("source.kind=log");
        a.sets.emplace_back(std::string("source.path=\"") + v + "\"");
      } else if (arg == "--record") {
        a.sets.emplace_back(std::string("recorder.path=\"") + v + "\"");
      } else {
        a.sets.emplace_back(std::string("sinks.tum=\"") + v + "\"");
      }
    } else {
      std::fprintf(stderr, "cleanslam: unknown argument %s\n%s", arg.c_str(), kUsage);
      return std::nullopt;
    }
  }
  return a;
}

constexpr const char* kNotTheRobot =
    "cleanslam: no arguments, and this machine has neither the CAN interface %s nor the camera "
    "%s: not the robot.\n"
    "On a PC, run it on a dataset folder or a recorded log:\n"
    "  cleanslam-sim default-room /tmp/ds && cleanslam --dataset /tmp/ds --tum /tmp/pose.tum\n"
    "  cleanslam --log LOG\n"
    "(cleanslam-replay DATASET --out DIR writes every output; tools/demo.sh does it all.)\n"
    "To wait for the robot's devices anyway: cleanslam --set source.kind=drivers. --help for "
    "more.\n";

// The robot's CAN interface or camera exists here.
bool robot_devices_present(const FirmwareConfig& c) {
  std::error_code ec;
  return std::filesystem::exists("/sys/class/net/" + c.source.can_interface, ec) ||
         std::filesystem::exists(c.source.camera_device, ec);
}

void print_messages(const ConfigResult& r) {
  for (const auto& w : r.warnings) {
    std::fprintf(stderr, "cleanslam: warning: %s\n", w.c_str());
  }
  for (const auto& e : r.errors) {
    std::fprintf(stderr, "cleanslam: error: %s\n", e.c_str());
  }
}

// What a log source skipped while replaying, and why.
void report_log_source(const readers::LogSource& source, const std::string& name, Loop* loop) {
  for (const std::string& m : source.messages()) {
    std::fprintf(stderr, "cleanslam: warning: %s\n", m.c_str());
  }
  const std::uint64_t n =
      source.payload_defects() + source.stamps_refused() + source.out_of_place();
  if (n > source.messages().size()) {
    std::fprintf(stderr, "cleanslam: warning: %s: %llu more record(s) skipped the same ways\n",
                 name.c_str(), static_cast<unsigned long long>(n - source.messages().size()));
  }
  if (loop != nullptr) {
    loop->count(Reject::kCorruptRecord, source.payload_defects(), true);
    loop->count(Reject::kTimeJump, source.stamps_refused(), true);
    loop->count(Reject::kOutOfOrder, source.out_of_place(), true);
  }
}

// The first file's configuration record is what a replay runs with: it must be the recorded one.
bool config_hash_checked(const readers::LogReader& reader, bool fatal) {
  if (!reader.has_config() || reader.config_hash_matches()) {
    return true;
  }
  std::fprintf(stderr,
               "cleanslam: %s: %s: the configuration record's hash (0x%016llx) is not that of its "
               "text: the configuration was altered after recording%s\n",
               fatal ? "error" : "warning", reader.name().c_str(),
               static_cast<unsigned long long>(reader.config_hash()),
               fatal ? "; a replay with it would not be the recorded run" : "");
  return !fatal;
}

// Suffix k of a rotated log's name (LOG.k), or 0.
int rotation_suffix(const std::string& path, std::string& base) {
  const std::size_t dot = path.find_last_of('.');
  base = path;
  if (dot == std::string::npos || dot + 1 == path.size() ||
      path.find_first_not_of("0123456789", dot + 1) != std::string::npos || path.size() - dot > 6) {
    return 0;
  }
  base = path.substr(0, dot);
  return std::stoi(path.substr(dot + 1));
}

// A replay must begin where the run began: in the file of index 0, and go on in order.
bool replayable_alone(const readers::LogReader& log, const std::string& path) {
  if (!log.join_error().empty()) {
    std::fprintf(stderr, "cleanslam: error: %s: %s: cannot replay\n", path.c_str(),
                 log.join_error().c_str());
    return false;
  }
  if (log.file_index() == 0) {
    return true;
  }
  std::string base;
  const int k = rotation_suffix(path, base);
  std::string files;
  std::string missing;
  for (int i = k + static_cast<int>(log.file_index()); i >= 1; --i) {
    const std::string name = base + "." + std::to_string(i);
    files += name + " ";
    std::error_code ec;
    if (missing.empty() && !std::filesystem::exists(name, ec)) {
      missing = name;
    }
  }
  files += base;
  std::fprintf(stderr,
               "cleanslam: error: %s is file %u of a rotated recording (its header's file index; "
               "0 is the file the run began in): it continues a run whose estimator state is not "
               "in it, so its outputs cannot be reproduced alone.\n",
               path.c_str(), log.file_index());
  if (!missing.empty()) {
    std::fprintf(stderr,
                 "cleanslam: %s, which the run's start needs, does not exist (deleted by "
                 "rotation: recorder.max_files): this recording cannot be replayed bit for bit; "
                 "--log runs it afresh from its first record\n",
                 missing.c_str());
    return false;
  }
  std::fprintf(stderr,
               "cleanslam: join the files oldest first and replay the join:\n  cat %s > "
               "joined.log && cleanslam --replay joined.log\n",
               files.c_str());
  return false;
}

void report_log_defects(const readers::LogReader& reader, Loop* loop) {
  if (reader.total_defects() == 0) {
    return;
  }
  for (int d = 0; d < static_cast<int>(readers::LogDefect::kCount); ++d) {
    const auto defect = static_cast<readers::LogDefect>(d);
    if (reader.defects(defect) > 0) {
      std::fprintf(stderr, "cleanslam: warning: %s: %llu %s record(s) skipped\n",
                   reader.name().c_str(), static_cast<unsigned long long>(reader.defects(defect)),
                   readers::to_string(defect));
    }
  }
  if (reader.defects(readers::LogDefect::kTruncated) > 0) {
    std::fprintf(stderr,
                 "cleanslam: warning: %s is truncated at byte %zu: replaying up to its last whole "
                 "record\n",
                 reader.name().c_str(), reader.truncated_at());
  }
  if (loop != nullptr) {
    loop->count(Reject::kCorruptRecord, reader.total_defects(), true);
  }
}

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

int run_normal(const Args& args) {
  ConfigResult cfg = load_config(args.config_path, args.sets);
  print_messages(cfg);
  if (!cfg.ok()) {
    return 2;
  }
  FirmwareConfig config = cfg.config;
  std::unique_ptr<hal::SensorSource> source;
  std::optional<readers::LogReader> log;
  const readers::DatasetSource* dataset = nullptr;
  const readers::LogSource* log_source = nullptr;
  std::unique_ptr<drivers::RobotDrivers> robot;
  bool uncalibrated = false;
  switch (config.source.kind) {
    case SourceSettings::Kind::kDataset: {
      readers::DatasetSource::Options options;
      options.load.max_span_ns = config.loop.max_span_ns;
      auto ds = readers::DatasetSource::open(config.source.path, options);
      if (!ds.ok()) {
        std::fprintf(stderr, "cleanslam: error: %s\n", ds.error().c_str());
        return 2;
      }
      for (const auto& w : ds->warnings()) {
        std::fprintf(stderr, "cleanslam: warning: %s\n", w.c_str());
      }
      if (config.calibration_from_dataset) {
        config.calibration = ds->calibration();
      }
      auto owned = std::make_unique<readers::DatasetSource>(std::move(ds.value()));
      dataset = owned.get();
      source = std::move(owned);
      break;
    }
    case SourceSettings::Kind::kLog: {
      log.emplace();
      if (!log->open(config.source.path)) {
        std::fprintf(stderr, "cleanslam: error: %s\n", log->error().c_str());
        return 2;
      }
      (void)config_hash_checked(*log, false);
      if (!log->join_error().empty()) {
        std::fprintf(stderr, "cleanslam: warning: %s: %s\n", log->name().c_str(),
                     log->join_error().c_str());
      }
      if (log->file_index() > 0) {
        std::fprintf(stderr,
                     "cleanslam: warning: %s is file %u of a rotated recording: the run starts "
                     "afresh at its first record, not where the recording was\n",
                     log->name().c_str(), log->file_index());
      }
      if (log->has_config()) {
        const ConfigResult recorded = parse_config(std::string(log->config_text()), "", {});
        if (recorded.ok()) {
          config.calibration = recorded.config.calibration;
        }
      }
      auto owned = std::make_unique<readers::LogSource>(
          *log, readers::LogSource::Pacing::kEventTime, config.loop.max_span_ns);
      log_source = owned.get();
      source = std::move(owned);
      break;
    }
    case SourceSettings::Kind::kDrivers: {
      if (args.config_path.empty() && args.sets.empty() && !robot_devices_present(config)) {
        std::fprintf(stderr, kNotTheRobot, config.source.can_interface.c_str(),
                     config.source.camera_device.c_str());
        return 2;
      }
      uncalibrated = !cfg.calibration_not_set.empty();
      if (uncalibrated) {
        std::fprintf(stderr, "cleanslam: warning: %s\n",
                     uncalibrated_message(cfg.calibration_not_set, args.config_path).c_str());
      }
      drivers::RobotDriversConfig dc;
      dc.can.interface = config.source.can_interface;
      dc.camera.device = config.source.camera_device;
      dc.camera.rate_hz = config.loop.frame_rate_hz;
      if (config.source.lift_line >= 0) {
        dc.lift.gpio.chip = config.source.gpio_chip;
        dc.lift.gpio.line = std::to_string(config.source.lift_line);
      }
      if (config.robot.status_led_line >= 0) {
        dc.status_led.chip = config.source.gpio_chip;
        dc.status_led.line = std::to_string(config.robot.status_led_line);
      }
      if (config.robot.gyro_ready_line >= 0) {
        dc.gyro_ready.gpio.chip = config.source.gpio_chip;
        dc.gyro_ready.gpio.line = std::to_string(config.robot.gyro_ready_line);
        dc.gyro_ready.max_latency_ns = hal::from_seconds(config.robot.gyro_ready_max_latency_s);
      }
      dc.pose_interface = config.sinks.can ? config.sinks.can_interface : std::string();
      robot = std::make_unique<drivers::RobotDrivers>(dc);
      break;
    }
  }
  const std::unique_ptr<Estimator> estimator = make_estimator(config);
  // The map first: a second process on the same map is refused before it writes any output.
  RunMap map(config.map, "cleanslam");
  if (map.refused()) {
    return 2;
  }
  Loop loop(loop_options(config), *estimator);
  if (robot) {
    for (int i = 0; i < robot->source_count(); ++i) {
      loop.add_source(robot->sources()[i]);
    }
    if (robot->pose_sink() != nullptr) {
      loop.add_pose_sink(robot->pose_sink());
    }
  } else {
    loop.add_source(source.get());
  }
  if (log) {
    report_log_defects(*log, &loop);
  }
  std::string error;
  TumWriter tum;
  if (!config.sinks.tum_path.empty()) {
    if (!tum.open(config.sinks.tum_path, false, true, error, config.sinks.rotation)) {
      std::fprintf(stderr, "cleanslam: error: %s\n", error.c_str());
      return 2;
    }
    loop.add_pose_sink(&tum);
  }
  DiagnosticsCsv diagnostics;
  const SinkSettings& k = config.sinks;
  if (!k.diagnostics_path.empty() && !diagnostics.open(k.diagnostics_path, error, k.rotation)) {
    std::fprintf(stderr, "cleanslam: error: %s\n", error.c_str());
    return 2;
  }
  loop.add_update_sink(&diagnostics);  // a CSV sink that was not opened writes nothing
  if (config.sinks.can && !robot) {
    std::fprintf(stderr,
                 "cleanslam: warning: sinks.can: the CAN pose sink needs source.kind: drivers; "
                 "ignored\n");
  }
  Recorder recorder;
  if (!config.recorder.path.empty()) {
    if (!recorder.open(config.recorder, config_text(config), error)) {
      std::fprintf(stderr, "cleanslam: error: %s\n", error.c_str());
      return 2;
    }
    loop.set_recorder(&recorder);
  }
  SystemdNotifier notifier;
  if (notifier.active()) {
    loop.set_notifier(&notifier);
  }
  HealthReport health("cleanslam", stderr);
  loop.set_health_observer(&health);
  LiveTask* saving = map.task();
  StopSignals signals;
  RunEnd end = RunEnd::kStopped;
  hal::TimeNs end_ns = 0;
  if (robot) {
    MonotonicClock clock;
    std::optional<StatusIndicator> indicator;
    if (robot->status_led() != nullptr) {
      indicator.emplace(*robot->status_led(), robot->inputs_missing() || uncalibrated);
    }
    TaskPair tasks(indicator ? &*indicator : nullptr, saving);
    end = run_live(loop, clock, signals, &tasks);
    end_ns = clock.now();
  } else {
    VirtualClock clock;
    end = run_virtual(loop, clock, config.source.realtime, &signals, saving);
    end_ns = clock.now();
  }
  recorder.close();
  const bool outputs_written =
      close_and_report_outputs("cleanslam", &tum, &diagnostics, &recorder, stderr);
  const bool map_saved = map.finish(*estimator, end_ns);
  if (log_source != nullptr) {
    report_log_source(*log_source, config.source.path, &loop);
  }
  if (dataset != nullptr) {
    loop.count(Reject::kTimeJump, dataset->summary().rows_refused, true);
    for (const std::string& m : dataset->image_error_messages()) {
      std::fprintf(stderr, "cleanslam: warning: %s\n", m.c_str());
    }
    const auto told = static_cast<int>(dataset->image_error_messages().size());
    if (dataset->image_errors() > told) {
      std::fprintf(stderr, "cleanslam: warning: %s: %d more image(s) could not be read\n",
                   config.source.path.c_str(), dataset->image_errors() - told);
    }
  }
  print_summary(loop, stderr);
  if (uncalibrated) {
    std::fprintf(stderr, "cleanslam: warning: %s\n",
                 uncalibrated_message(cfg.calibration_not_set, args.config_path).c_str());
  }
  if (end == RunEnd::kStopped) {
    std::fprintf(stderr, "cleanslam: stopped by signal, outputs flushed\n");
  }
  if (dataset != nullptr && !dataset->stream_error().empty()) {
    std::fprintf(stderr, "cleanslam: error: %s\n", dataset->stream_error().c_str());
    return 2;
  }
  return map_saved && outputs_written ? 0 : 2;
}

void print_camera_offset(const CameraOffsetEstimate::Result& c, std::FILE* out) {
  if (!c.measurable) {
    std::fprintf(out,
                 "cleanslam: camera time offset: not measurable (%llu points seen in consecutive "
                 "frames; it needs turning with points in view)\n",
                 static_cast<unsigned long long>(c.pairs));
    return;
  }
  std::fprintf(
      out,
      "cleanslam: camera time offset: the data suggest %+.3f s (+- %.4f s from the "
      "scatter, %llu points seen in consecutive frames); camera.time_offset_s is %+.3f s\n",
      c.suggested_s, c.std_s, static_cast<unsigned long long>(c.pairs), c.configured_s);
  const double d = c.suggested_s - c.configured_s;
  if (std::abs(d) > CameraOffsetEstimate::kWarnS && std::abs(d) > 3.0 * c.std_s) {
    std::fprintf(out, "cleanslam: warning: camera.time_offset_s looks off by %+.3f s\n", d);
  }
}
}  // namespace

LoopOptions loop_options(const FirmwareConfig& config) {
  LoopOptions o = config.loop;
  o.camera = config.calibration.camera;
  return o;
}

void print_summary(const Loop& loop, std::FILE* out) {
  const LoopStats& s = loop.stats();
  std::fprintf(
      out,
      "cleanslam: %llu iterations, %llu gyro, %llu encoder samples, %llu frames in, %llu "
      "processed, %llu predictions, %llu poses, %llu update records\n",
      static_cast<unsigned long long>(s.iterations), static_cast<unsigned long long>(s.gyro),
      static_cast<unsigned long long>(s.encoders), static_cast<unsigned long long>(s.frames_in),
      static_cast<unsigned long long>(s.frames_done),
      static_cast<unsigned long long>(s.predictions), static_cast<unsigned long long>(s.poses),
      static_cast<unsigned long long>(s.update_records));
  std::fputs("cleanslam: update records by status:", out);
  const char* separator = "";
  for (std::size_t i = 0; i < s.records_by_status.size(); ++i) {
    if (s.records_by_status[i] > 0) {
      std::fprintf(out, "%s %s %llu", separator, to_string(static_cast<hal::log::UpdateStatus>(i)),
                   static_cast<unsigned long long>(s.records_by_status[i]));
      separator = ",";
    }
  }
  std::fputs(separator[0] == '\0' ? " none\n" : "\n", out);
  for (std::size_t i = 0; i < s.records_by_status.size(); ++i) {
    if (s.records_by_status[i] > 0) {
      const auto status = static_cast<hal::log::UpdateStatus>(i);
      std::fprintf(out, "cleanslam:   %-14s %llu %s\n", to_string(status),
                   static_cast<unsigned long long>(s.records_by_status[i]), explain(status));
    }
  }
  const MapCounters m = loop.estimator().map_counters();
  std::fprintf(
      out,
      "cleanslam: map: %llu landmarks initialized, %llu replaced, %llu deleted, %llu "
      "merged, %llu merges gated\n",
      static_cast<unsigned long long>(m.initialized), static_cast<unsigned long long>(m.replaced),
      static_cast<unsigned long long>(m.deleted), static_cast<unsigned long long>(m.merged),
      static_cast<unsigned long long>(m.merges_gated));
  const ObservationRejections r = loop.estimator().observation_rejections();
  if (r.count > 0) {
    std::fputs("cleanslam: measurements not fused:", out);
    for (int i = 0; i < r.count; ++i) {
      const ObservationRejection& e = r.by_reason[static_cast<std::size_t>(i)];
      std::fprintf(out, "%s %s %llu", i > 0 ? "," : "", e.reason,
                   static_cast<unsigned long long>(e.count));
    }
    std::fputc('\n', out);
    for (int i = 0; i < r.count; ++i) {
      const ObservationRejection& e = r.by_reason[static_cast<std::size_t>(i)];
      std::fprintf(out, "cleanslam:   %-14s %s\n", e.reason, explain_observation_reason(e.reason));
    }
  }
  WheelYawReport w;
  if (loop.estimator().wheel_yaw(w)) {
    std::fprintf(out,
                 "cleanslam: wheel heading: scale %+.4f (std. dev. %.4f), drift %+.4f rad/m (std. "
                 "dev. %.4f), gyro bias %+.5f rad/s; %llu intervals fused, %llu gated, %llu "
                 "windows learnt, %llu taken back to the gyro\n",
                 w.scale, w.scale_std, w.drift_rad_per_m, w.drift_std, w.gyro_bias_rad_s,
                 static_cast<unsigned long long>(w.intervals_fused),
                 static_cast<unsigned long long>(w.intervals_gated),
                 static_cast<unsigned long long>(w.windows_used),
                 static_cast<unsigned long long>(w.windows_gated));
  }
  print_camera_offset(loop.camera_offset(), out);
  for (std::size_t i = 0; i < kRejectCount; ++i) {
    if (s.rejects.n[i] > 0) {
      std::fprintf(out, "cleanslam: rejected %s: %llu %s\n", to_string(static_cast<Reject>(i)),
                   static_cast<unsigned long long>(s.rejects.n[i]),
                   explain(static_cast<Reject>(i)));
    }
  }
}

bool write_landmarks_csv(const Estimator& estimator, const std::string& path, std::string& error) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) {
    error = path + ": cannot create: " + std::strerror(errno);
    return false;
  }
  std::array<LandmarkEstimate, hal::kMaxLandmarks> lm{};
  const int n = estimator.landmarks(lm.data(), static_cast<int>(lm.size()));
  std::fputs("#slot,x,y,z,sxx,sxy,sxz,syy,syz,szz\n", f);
  for (int i = 0; i < n; ++i) {
    const auto& l = lm[static_cast<std::size_t>(i)];
    const auto& c = l.covariance;
    std::fprintf(f, "%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", l.slot, l.position_m[0],
                 l.position_m[1], l.position_m[2], c[0], c[1], c[2], c[4], c[5], c[8]);
  }
  return std::fclose(f) == 0;
}

int program_main(int argc, char** argv) {
  const auto args = parse_args(argc, argv);
  if (!args) {
    return 2;
  }
  if (args->help) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (args->version) {
    std::printf("cleanslam 0.1.0\n");
    return 0;
  }
  if (args->print_sample_config) {
    std::fputs(sample_config_text().c_str(), stdout);
    return 0;
  }
  if (!args->replay_log.empty()) {
    return run_replay(*args);
  }
  return run_normal(*args);
}

}  // namespace cleanslam::firmware
