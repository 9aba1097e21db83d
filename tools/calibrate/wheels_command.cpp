// cleanslam-calibrate wheels DATASET --straight METRES: ticks per metre and wheel base.
#include <cstdio>
#include <numbers>
#include <string>

#include "cleanslam/calibrate/text.hpp"
#include "cleanslam/calibrate/wheel_calibration.hpp"
#include "command_line.hpp"
#include "commands.hpp"
#include "inputs.hpp"

namespace cleanslam::calibrate {
namespace {

void wheels_usage(std::FILE* out) {
  std::fprintf(out,
               "usage: %s wheels DATASET|LOG --straight METRES [options]\n"
               "  DATASET|LOG a recording of the calibration drive (a dataset folder, or a\n"
               "              log the firmware recorded: cleanslam --record LOG): standing\n"
               "              still, then a straight forward drive, then turns in place\n"
               "  --straight METRES  the straight drive's measured length\n"
               "  --min-standstill S the standstill before the first motion (default 3 s)\n"
               "%s",
               kProgram, kOutputUsage);
}

}  // namespace

int wheels_command(int argc, char** argv) {
  CommandLine line =
      parse_command_line(argc, argv, 1, {"--straight", "--min-standstill"}, {"-h", "--help"});
  if (line.flags.count("-h") || line.flags.count("--help")) {
    wheels_usage(stdout);
    return 0;
  }
  WheelCalibrationOptions options;
  options.straight_length_m = line.number("--straight", 0.0);
  options.min_standstill_s = line.number("--min-standstill", options.min_standstill_s);
  if (line.error.empty() && line.positional.size() != 1) {
    line.error = "expected one DATASET (a folder) or LOG (a firmware log)";
  }
  if (line.error.empty() && !line.has("--straight")) {
    line.error = "--straight METRES: the straight drive's measured length is needed";
  }
  if (!line.error.empty()) {
    tell("wheels", line.error);
    wheels_usage(stderr);
    return 2;
  }
  const std::string folder = line.positional.front();
  const std::optional<readers::Dataset> dataset = read_recording("wheels", folder);
  if (!dataset) {
    return 1;
  }
  auto c = calibrate_wheels(*dataset, options);
  if (!c.ok()) {
    tell("wheels", c.error());
    return 1;
  }
  constexpr double kDeg = 180.0 / std::numbers::pi;
  CalibrationResult r;
  r.method = {
      std::string(kProgram) + " wheels " + folder + " --straight " +
          significant(options.straight_length_m, 6),
      "Ticks per metre: each wheel's ticks over the straight drive / its length, less "
      "+-wheel_base/2",
      "times the gyro's heading change over it (" + fixed(c->straight_yaw_rad * kDeg, 2) +
          " deg); straight drive " + fixed(c->straight_ticks_left, 0) + " / " +
          fixed(c->straight_ticks_right, 0) + " ticks (left / right).",
      "Wheel base: the wheels' distance difference / the gyro's angle over " +
          std::to_string(c->turns) + " turns in place (" + fixed(c->turn_angle_rad * kDeg, 0) +
          " deg in all; spread between turns " + significant(c->wheel_base_spread_m, 2) + " m).",
      "Gyro bias " + significant(c->gyro_bias_rad_s, 3) + " rad/s from the first " +
          fixed(c->standstill_s, 1) + " s standing still; the gyro's scale is taken as exact.",
  };
  if (c->mixed_intervals > 0) {
    r.method.push_back(std::to_string(c->mixed_intervals) +
                       " encoder intervals with one wheel still were left out (neither kind).");
  }
  r.keys = {
      {"wheels", "ticks_per_meter_left", {c->ticks_per_meter_left}, false, "ticks per metre"},
      {"wheels", "ticks_per_meter_right", {c->ticks_per_meter_right}, false, "ticks per metre"},
      {"wheels", "wheel_base", {c->wheel_base_m}, false, "metres"},
  };
  std::fprintf(stderr,
               "%s wheels: ticks per metre left %.2f, right %.2f; wheel base %.5f m "
               "(%d turns, %.0f deg)\n",
               kProgram, c->ticks_per_meter_left, c->ticks_per_meter_right, c->wheel_base_m,
               c->turns, c->turn_angle_rad * kDeg);
  return emit(kProgram, line, r, {folder});
}

}  // namespace cleanslam::calibrate
