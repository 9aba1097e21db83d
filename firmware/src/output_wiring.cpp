#include "output_wiring.hpp"

#include <string>

namespace cleanslam::firmware {

bool wire_outputs(const FirmwareConfig& config, bool on_robot, Loop& loop, RunOutputs& out) {
  std::string error;
  if (!config.sinks.tum_path.empty()) {
    if (!out.tum.open(config.sinks.tum_path, false, true, error, config.sinks.rotation)) {
      std::fprintf(stderr, "cleanslam: error: %s\n", error.c_str());
      return false;
    }
    loop.add_pose_sink(&out.tum);
  }
  const SinkSettings& k = config.sinks;
  if (!k.diagnostics_path.empty() && !out.diagnostics.open(k.diagnostics_path, error, k.rotation)) {
    std::fprintf(stderr, "cleanslam: error: %s\n", error.c_str());
    return false;
  }
  loop.add_update_sink(&out.diagnostics);
  if (config.sinks.can && !on_robot) {
    std::fprintf(stderr,
                 "cleanslam: warning: sinks.can: the CAN pose sink needs source.kind: drivers; "
                 "ignored\n");
  }
  if (!config.recorder.path.empty()) {
    if (!out.recorder.open(config.recorder, config_text(config), error)) {
      std::fprintf(stderr, "cleanslam: error: %s\n", error.c_str());
      return false;
    }
    loop.set_recorder(&out.recorder);
  }
  if (out.notifier.active()) {
    loop.set_notifier(&out.notifier);
  }
  loop.set_health_observer(&out.health);
  loop.add_update_sink(&out.camera_offset);
  loop.add_gyro_sink(&out.camera_offset);
  return true;
}

}  // namespace cleanslam::firmware
