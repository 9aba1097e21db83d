// cleanslam-calibrate gyro DATASET: the gyro's bias and noise density from a standstill.
#include <cstdio>
#include <string>

#include "cleanslam/calibrate/allan_deviation.hpp"
#include "cleanslam/calibrate/text.hpp"
#include "command_line.hpp"
#include "commands.hpp"
#include "inputs.hpp"

namespace cleanslam::calibrate {
namespace {

void gyro_usage(std::FILE* out) {
  std::fprintf(out,
               "usage: %s gyro DATASET|LOG [options]\n"
               "  DATASET|LOG a recording of the robot standing still (a dataset folder, or a\n"
               "              log the firmware recorded: cleanslam --record LOG)\n"
               "  --min-duration S  refuse a shorter recording (default 100 s)\n"
               "  --curve FILE      also write the Allan deviation curve (CSV)\n"
               "%s",
               kProgram, kOutputUsage);
}

}  // namespace

int gyro_command(int argc, char** argv) {
  CommandLine line =
      parse_command_line(argc, argv, 1, {"--min-duration", "--curve"}, {"-h", "--help"});
  if (line.flags.count("-h") || line.flags.count("--help")) {
    gyro_usage(stdout);
    return 0;
  }
  GyroNoiseOptions options;
  options.min_duration_s = line.number("--min-duration", options.min_duration_s);
  if (line.error.empty() && line.positional.size() != 1) {
    line.error = "expected one DATASET (a folder) or LOG (a firmware log)";
  }
  if (!line.error.empty()) {
    tell("gyro", line.error);
    gyro_usage(stderr);
    return 2;
  }
  const std::string folder = line.positional.front();
  const std::optional<readers::Dataset> dataset = read_recording("gyro", folder);
  if (!dataset) {
    return 1;
  }
  std::fprintf(stderr, "%s gyro: Allan deviation of %zu samples\n", kProgram, dataset->gyro.size());
  auto n = gyro_noise(*dataset, options);
  if (!n.ok()) {
    tell("gyro", n.error());
    return 1;
  }
  if (line.has("--curve")) {
    std::string csv = "#tau_s,deviation_rad_s\n";
    for (const AllanPoint& p : n->curve) {
      csv += significant(p.tau_s, 6) + "," + significant(p.deviation_rad_s, 6) + "\n";
    }
    const std::string& path = line.values.at("--curve");
    if (readers::Status s =
            write_calibration_file(path, csv, line.flags.count("--force") > 0, {folder});
        !s) {
      tell("gyro", s.error());
      return 1;
    }
  }
  CalibrationResult r;
  r.method = {
      std::string(kProgram) + " gyro " + folder + ": " + fixed(n->duration_s, 1) +
          " s standing still, " + std::to_string(n->samples) + " samples at " +
          fixed(n->rate_hz, 1) + " Hz.",
      "Overlapping Allan deviation (IEEE 952): noise density = the deviation at tau = 1 s;",
      "the fit of the -1/2 slope over tau 10 samples .. 1 s gives " +
          significant(n->slope_fit_density, 4) + ". Bias instability = the curve's minimum",
      "(at tau = " + significant(n->bias_instability_tau_s, 3) +
          " s) / 0.664. Bias (the mean rate) " + significant(n->bias_rad_s, 4) +
          " rad/s: it changes at every power-up, not a key.",
  };
  r.keys = {
      {"gyro", "noise_density", {n->noise_density}, false, "rad/s/sqrt(Hz)"},
      {"gyro", "bias_instability", {n->bias_instability}, false, "rad/s"},
  };
  std::fprintf(stderr,
               "%s gyro: bias %.4g rad/s, noise density %.4g rad/s/sqrt(Hz) (slope fit %.4g), "
               "bias instability %.3g rad/s\n",
               kProgram, n->bias_rad_s, n->noise_density, n->slope_fit_density,
               n->bias_instability);
  return emit(kProgram, line, r, {folder});
}

}  // namespace cleanslam::calibrate
