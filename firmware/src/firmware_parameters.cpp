#include "cleanslam/firmware/firmware_parameters.hpp"

#include <array>
#include <string_view>

namespace cleanslam::firmware {

namespace {

using hal::choice_field;
using hal::mebibytes_field;
using hal::parameter_field;
using hal::seconds_field;
using P = hal::Parameter<FirmwareConfig>;
using C = FirmwareConfig;

constexpr std::array<std::string_view, 3> kSourceKinds{"drivers", "dataset", "log"};

// Key, member, default, range (lo, hi, lo open), unit, meaning. A text's default is the struct's.
constexpr std::array kFirmwareParameters{
    P{"calibration_from_dataset", [](C& c) { return parameter_field(c.calibration_from_dataset); },
      1.0, 0.0, 1.0, false, "",
      "a dataset source brings its own sensors.yaml (true) or uses the calibration section"},

    P{"loop.frame_rate_hz", [](C& c) { return parameter_field(c.loop.frame_rate_hz); }, 2.0, 0.1,
      30.0, false, "Hz", "frames are taken at most this often; newer ones replace waiting ones"},
    P{"loop.publish_rate_hz", [](C& c) { return parameter_field(c.loop.publish_rate_hz); }, 20.0,
      1.0, 200.0, false, "Hz", "pose publication"},
    P{"loop.gyro_timeout_s", [](C& c) { return seconds_field(c.loop.gyro_timeout_ns); }, 0.1, 0.001,
      10.0, false, "s", "gyro silent beyond this: heading from the encoders, inflated noise"},
    P{"loop.encoder_timeout_s", [](C& c) { return seconds_field(c.loop.encoder_timeout_ns); }, 0.25,
      0.001, 10.0, false, "s", "encoders silent beyond this: flagged, motion model"},
    P{"loop.camera_timeout_s", [](C& c) { return seconds_field(c.loop.camera_timeout_ns); }, 3.0,
      0.01, 60.0, false, "s", "camera silent beyond this: dead reckoning only, flagged"},
    P{"loop.max_span_s", [](C& c) { return seconds_field(c.loop.max_span_ns); }, 86400.0, 1.0,
      3.0e7, false, "s", "a sample stamped this long after the start is a time jump"},
    P{"loop.frame_work_budget", [](C& c) { return parameter_field(c.loop.frame_work_budget); },
      64.0, 1.0, 1048576.0, false, "",
      "frame pipeline work units per loop iteration (an EKF update step: 32768 instructions each)"},

    P{"source.kind", [](C& c) { return choice_field(c.source.kind, kSourceKinds); }, 0.0, 0.0, 0.0,
      false, "", "where the sensors' data come from"},
    P{"source.path", [](C& c) { return parameter_field(c.source.path); }, 0.0, 0.0, 0.0, false, "",
      "dataset folder or log file (dataset, log)"},
    P{"source.realtime", [](C& c) { return parameter_field(c.source.realtime); }, 0.0, 0.0, 1.0,
      false, "",
      "dataset, log: paced in real time (true) or as fast as possible on a virtual clock"},
    P{"source.camera_device", [](C& c) { return parameter_field(c.source.camera_device); }, 0.0,
      0.0, 0.0, false, "", "drivers: the V4L2 camera"},
    P{"source.can_interface", [](C& c) { return parameter_field(c.source.can_interface); }, 0.0,
      0.0, 0.0, false, "", "drivers: gyro and encoders from the base board"},
    P{"source.gpio_chip", [](C& c) { return parameter_field(c.source.gpio_chip); }, 0.0, 0.0, 0.0,
      false, "", "drivers: the GPIO chip of the robot's lines"},
    P{"source.lift_line", [](C& c) { return parameter_field(c.source.lift_line); }, -1.0, -1.0,
      1023.0, false, "", "drivers: GPIO line of the wheel-drop switch, -1: none"},

    P{"sinks.tum", [](C& c) { return parameter_field(c.sinks.tum_path); }, 0.0, 0.0, 0.0, false, "",
      "TUM trajectory file (t x y z qx qy qz qw), \"\" for none"},
    P{"sinks.diagnostics", [](C& c) { return parameter_field(c.sinks.diagnostics_path); }, 0.0, 0.0,
      0.0, false, "", "per-update diagnostics records (CSV), \"\" for none"},
    P{"sinks.can", [](C& c) { return parameter_field(c.sinks.can); }, 0.0, 0.0, 1.0, false, "",
      "drivers: publish the pose as CAN frames (0x201, 0x202 of docs/can.md)"},
    P{"sinks.can_interface", [](C& c) { return parameter_field(c.sinks.can_interface); }, 0.0, 0.0,
      0.0, false, "", "the CAN interface of the pose frames"},
    P{"sinks.max_file_mb", [](C& c) { return mebibytes_field(c.sinks.rotation.max_file_bytes); },
      64.0, 1.0, 1e5, false, "MiB", "tum, tum.cov, diagnostics: rotated beyond this size"},
    P{"sinks.max_files", [](C& c) { return parameter_field(c.sinks.rotation.max_files); }, 4.0, 1.0,
      1000.0, false, "", "path, path.1 .. path.(max_files-1) kept of each"},

    P{"recorder.path", [](C& c) { return parameter_field(c.recorder.path); }, 0.0, 0.0, 0.0, false,
      "", "binary log of everything crossing the hal boundary, \"\" for none"},
    P{"recorder.max_file_mb", [](C& c) { return mebibytes_field(c.recorder.max_file_bytes); }, 64.0,
      1.0, 1e5, false, "MiB", "rotated beyond this size"},
    P{"recorder.max_files", [](C& c) { return parameter_field(c.recorder.max_files); }, 4.0, 1.0,
      1000.0, false, "", "path, path.1 .. path.(max_files-1) kept"},
    P{"recorder.frame_every", [](C& c) { return parameter_field(c.recorder.frame_every); }, 1.0,
      0.0, 1e6, false, "", "every k-th frame recorded (0: none); a bit-exact replay needs 1"},

    P{"robot.status_led_line", [](C& c) { return parameter_field(c.robot.status_led_line); }, -1.0,
      -1.0, 1023.0, false, "",
      "GPIO output of the status LED (steady: OK, 1 Hz: degraded, 4 Hz: fault), -1: none"},
    P{"robot.gyro_ready_line", [](C& c) { return parameter_field(c.robot.gyro_ready_line); }, -1.0,
      -1.0, 1023.0, false, "",
      "GPIO input, rising edge = gyro sampled: stamps CAN gyro frames, -1: CAN reception time"},

    P{"map.path", [](C& c) { return parameter_field(c.map.path); }, 0.0, 0.0, 0.0, false, "",
      "the map file, \"\" for none (the robot's package: /var/lib/cleanslam/map.bin)"},
    P{"map.save_interval_s", [](C& c) { return parameter_field(c.map.save_interval_s); }, 300.0,
      0.1, 86400.0, false, "s",
      "a save holds the loop while it writes and syncs the map, so at most ten a second; saved "
      "this often while running and at the end of a run"},
};

}  // namespace

std::span<const hal::Parameter<FirmwareConfig>> firmware_parameters() {
  return kFirmwareParameters;
}

}  // namespace cleanslam::firmware
