#pragma once

#include <span>
#include <string>
#include <vector>

#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/firmware/map_store.hpp"
#include "cleanslam/firmware/recorder.hpp"
#include "cleanslam/firmware/rotating_file.hpp"
#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/readers/result.hpp"
#include "cleanslam/slam_core/parameter_table.hpp"

namespace cleanslam::firmware {

struct SourceSettings {
  enum class Kind { kDrivers, kDataset, kLog };
  Kind kind = Kind::kDrivers;
  std::string path;       // dataset folder or log file
  bool realtime = false;  // pace a dataset or log in real time instead of as fast as possible
  std::string camera_device = "/dev/video0";
  std::string can_interface = "can0";
  std::string gpio_chip = "/dev/gpiochip0";
  int lift_line = -1;  // GPIO line of the wheel-drop switch; -1: none
};

struct SinkSettings {
  std::string tum_path;                // TUM trajectory file; empty: none
  std::string diagnostics_path;        // per-update records (CSV); empty: none
  bool can = false;                    // CAN pose frame through the driver
  std::string can_interface = "can0";  // pose frames 0x201/0x202 of docs/can.md
  // The TUM file, its .cov and the diagnostics rotate as the recorder's log does.
  Rotation rotation{std::size_t{64} << 20, 4};
};

// The robot's GPIO wiring (lines of source.gpio_chip). What the wheel-drop switch means
// (map_management.on_set_down, relocalize_std_m, relocalize_std_yaw_deg) is the estimator's
// slam_core::MapConfig.
struct RobotSettings {
  int status_led_line = -1;  // GPIO output: steady OK, slow blink degraded, fast blink fault
  int gyro_ready_line = -1;  // GPIO input, rising edge when the gyro sampled; -1: CAN time
  double gyro_ready_max_latency_s = 0.008;  // edge to CAN reception, at most
};

struct FirmwareConfig {
  hal::Calibration calibration;
  bool calibration_from_dataset = true;  // a dataset source brings its own sensors.yaml
  // The estimator: the keys of slam_core::slam_parameters() (sections filter and frontend).
  slam_core::SlamConfig slam;
  LoopOptions loop;
  SourceSettings source;
  SinkSettings sinks;
  RecorderOptions recorder;
  RobotSettings robot;
  MapStoreOptions map;
};

struct ConfigResult {
  FirmwareConfig config;
  std::vector<std::string> warnings;
  std::vector<std::string> errors;  // each names the file, line and key
  // The keys of kMeasuredCalibrationKeys that neither the file nor an override sets.
  std::vector<std::string> calibration_not_set;
  [[nodiscard]] bool ok() const { return errors.empty(); }
};

// Reads `path` (empty: all defaults), applies "key.sub=value" overrides, validates every key.
ConfigResult load_config(const std::string& path, const std::vector<std::string>& overrides);
// The same from a text (a recorded configuration).
ConfigResult parse_config(const std::string& text, const std::string& file_name,
                          const std::vector<std::string>& overrides);
// Every key with its value, in a form parse_config() reads back to the same configuration.
std::string config_text(const FirmwareConfig& config);
// firmware/config/cleanslam.sample.yaml: every key with its default, range and meaning.
std::string sample_config_text();

}  // namespace cleanslam::firmware
