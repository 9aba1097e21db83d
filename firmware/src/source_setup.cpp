#include "source_setup.hpp"

#include <cstdio>
#include <filesystem>
#include <string>

#include "cleanslam/firmware/robot_calibration.hpp"
#include "log_reports.hpp"

namespace cleanslam::firmware {

namespace {

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

}  // namespace

void RunSources::add_to(Loop& loop) const {
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
}

bool open_sources(const Args& args, const ConfigResult& cfg, FirmwareConfig& config,
                  RunSources& s) {
  switch (config.source.kind) {
    case SourceSettings::Kind::kDataset: {
      readers::DatasetSource::Options options;
      options.load.max_span_ns = config.loop.max_span_ns;
      auto ds = readers::DatasetSource::open(config.source.path, options);
      if (!ds.ok()) {
        std::fprintf(stderr, "cleanslam: error: %s\n", ds.error().c_str());
        return false;
      }
      for (const auto& w : ds->warnings()) {
        std::fprintf(stderr, "cleanslam: warning: %s\n", w.c_str());
      }
      if (config.calibration_from_dataset) {
        config.calibration = ds->calibration();
      }
      auto owned = std::make_unique<readers::DatasetSource>(std::move(ds.value()));
      s.dataset = owned.get();
      s.source = std::move(owned);
      break;
    }
    case SourceSettings::Kind::kLog: {
      s.log.emplace();
      if (!s.log->open(config.source.path)) {
        std::fprintf(stderr, "cleanslam: error: %s\n", s.log->error().c_str());
        return false;
      }
      (void)config_hash_checked(*s.log, false);
      if (!s.log->join_error().empty()) {
        std::fprintf(stderr, "cleanslam: warning: %s: %s\n", s.log->name().c_str(),
                     s.log->join_error().c_str());
      }
      if (s.log->file_index() > 0) {
        std::fprintf(stderr,
                     "cleanslam: warning: %s is file %u of a rotated recording: the run starts "
                     "afresh at its first record, not where the recording was\n",
                     s.log->name().c_str(), s.log->file_index());
      }
      if (s.log->has_config()) {
        const ConfigResult recorded = parse_config(std::string(s.log->config_text()), "", {});
        if (recorded.ok()) {
          config.calibration = recorded.config.calibration;
        }
      }
      auto owned = std::make_unique<readers::LogSource>(
          *s.log, readers::LogSource::Pacing::kEventTime, config.loop.max_span_ns);
      s.log_source = owned.get();
      s.source = std::move(owned);
      break;
    }
    case SourceSettings::Kind::kDrivers: {
      if (args.config_path.empty() && args.sets.empty() && !robot_devices_present(config)) {
        std::fprintf(stderr, kNotTheRobot, config.source.can_interface.c_str(),
                     config.source.camera_device.c_str());
        return false;
      }
      s.uncalibrated = !cfg.calibration_not_set.empty();
      if (s.uncalibrated) {
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
      s.robot = std::make_unique<drivers::RobotDrivers>(dc);
      break;
    }
  }
  return true;
}

void report_sources(const RunSources& s, const FirmwareConfig& config, Loop& loop) {
  if (s.log_source != nullptr) {
    report_log_source(*s.log_source, config.source.path, &loop);
  }
  if (s.dataset != nullptr) {
    loop.count(Reject::kTimeJump, s.dataset->summary().rows_refused, true);
    for (const std::string& m : s.dataset->image_error_messages()) {
      std::fprintf(stderr, "cleanslam: warning: %s\n", m.c_str());
    }
    const auto told = static_cast<int>(s.dataset->image_error_messages().size());
    if (s.dataset->image_errors() > told) {
      std::fprintf(stderr, "cleanslam: warning: %s: %d more image(s) could not be read\n",
                   config.source.path.c_str(), s.dataset->image_errors() - told);
    }
  }
}

}  // namespace cleanslam::firmware
