#pragma once

#include <cstdio>

#include "cleanslam/firmware/camera_offset_estimate.hpp"
#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/health_report.hpp"
#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/firmware/recorder.hpp"
#include "cleanslam/firmware/sinks.hpp"
#include "cleanslam/firmware/systemd_notifier.hpp"

// What a run writes and tells, on the loop: the TUM trajectory, the diagnostics CSV, the recorder,
// systemd's notifications, the health report and the camera time offset the data suggest.
namespace cleanslam::firmware {

struct RunOutputs {
  explicit RunOutputs(const hal::CameraCalibration& camera) : camera_offset(camera) {}

  TumWriter tum;
  DiagnosticsCsv diagnostics;  // one that was not opened writes nothing
  Recorder recorder;
  SystemdNotifier notifier;
  HealthReport health{"cleanslam", stderr};
  CameraOffsetEstimate camera_offset;
};

// Opens the outputs config.sinks and config.recorder name and puts them on the loop; `on_robot`:
// the sources are the robot's drivers (the CAN pose sink needs them). False after an error
// message: no run.
bool wire_outputs(const FirmwareConfig& config, bool on_robot, Loop& loop, RunOutputs& out);

}  // namespace cleanslam::firmware
