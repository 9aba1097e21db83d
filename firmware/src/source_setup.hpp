#pragma once

#include <memory>
#include <optional>

#include "cleanslam/drivers/robot_drivers.hpp"
#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/hal/interfaces.hpp"
#include "cleanslam/readers/dataset_source.hpp"
#include "cleanslam/readers/log_source.hpp"
#include "program_args.hpp"

// The sensors of a run: a dataset folder, a recorded log or the robot's drivers, with what the
// end of the run reports of them.
namespace cleanslam::firmware {

struct RunSources {
  std::unique_ptr<hal::SensorSource> source;  // a dataset or a log
  std::optional<readers::LogReader> log;      // the log a LogSource reads
  const readers::DatasetSource* dataset = nullptr;
  const readers::LogSource* log_source = nullptr;
  std::unique_ptr<drivers::RobotDrivers> robot;
  bool uncalibrated = false;  // the robot with measured calibration keys left at the sample's

  RunSources() = default;
  RunSources(const RunSources&) = delete;  // a LogSource holds a reference to `log`
  RunSources& operator=(const RunSources&) = delete;

  // The sources (and the robot's CAN pose sink) on the loop.
  void add_to(Loop& loop) const;
};

// Opens the sources config.source names; a dataset's or a log's calibration replaces
// config.calibration as the configuration says. False after an error message: no run.
bool open_sources(const Args& args, const ConfigResult& cfg, FirmwareConfig& config, RunSources& s);

// After the run: what a log source skipped, a dataset's refused rows and unreadable images.
void report_sources(const RunSources& s, const FirmwareConfig& config, Loop& loop);

}  // namespace cleanslam::firmware
