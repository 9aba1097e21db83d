#include "cleanslam/firmware/program.hpp"

#include <cstdio>

#include "program_args.hpp"
#include "program_runs.hpp"

namespace cleanslam::firmware {

LoopOptions loop_options(const FirmwareConfig& config) {
  LoopOptions o = config.loop;
  o.camera = config.calibration.camera;
  return o;
}

int program_main(int argc, char** argv) {
  const auto args = parse_args(argc, argv);
  if (!args) {
    return 2;
  }
  if (args->help) {
    std::fputs(usage_text(), stdout);
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
