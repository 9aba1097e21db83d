// cleanslam-sim SCENARIO OUT_DIR [--seed N] [--set key=value ...]: simulates a scenario (built-in
// name or YAML file) and writes a dataset folder.
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/scenario_parameters.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"

namespace {

void usage(std::FILE* out) {
  std::fprintf(out,
               "usage: cleanslam-sim SCENARIO OUT_DIR [--seed N] [--set key=value ...]\n"
               "  SCENARIO  a built-in scenario name or a scenario YAML file\n"
               "  OUT_DIR   dataset folder to write (created; must be empty or absent)\n"
               "  --force   write into a non-empty OUT_DIR, first deleting the dataset files\n"
               "            (sensors.yaml, *.csv, cam0/) of an earlier run there\n"
               "  --seed N  override the scenario's seed\n"
               "  --set k=v override one scenario value, e.g. --set camera.rate_hz=1\n"
               "  --list    print the built-in scenarios, each with its description\n"
               "  --keys    print every scenario key with its default, unit, range and meaning\n");
}

// A scenario's description: the comment its YAML text starts with.
std::string description(const std::string& yaml) {
  std::string text;
  std::size_t at = 0;
  while (at < yaml.size() && yaml[at] == '#') {
    const std::size_t end = std::min(yaml.find('\n', at), yaml.size());
    std::string line = yaml.substr(at + 1, end - at - 1);
    line.erase(0, line.find_first_not_of(' '));
    text += (text.empty() ? "" : " ") + line;
    at = end + 1;
  }
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  namespace sim = cleanslam::sim_hal::sim;
  std::vector<std::string> positional;
  std::vector<std::string> overrides;
  bool force = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    }
    if (a == "--list") {
      for (const auto& n : sim::builtin_scenario_names()) {
        std::printf("%-22s %s\n", n.c_str(), description(sim::builtin_scenario_text(n)).c_str());
      }
      return 0;
    }
    if (a == "--keys") {
      std::fputs(sim::scenario_keys_text().c_str(), stdout);
      return 0;
    }
    if (a == "--force") {
      force = true;
      continue;
    }
    if (a == "--seed" || a == "--set") {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "cleanslam-sim: %s needs a value\n", argv[i]);
        return 2;
      }
      const std::string_view v = argv[++i];
      if (a == "--seed") {
        unsigned long long seed = 0;
        auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), seed);
        if (ec != std::errc() || ptr != v.data() + v.size()) {
          std::fprintf(stderr,
                       "cleanslam-sim: --seed: expected a non-negative integer, got \"%s\"\n",
                       argv[i]);
          return 2;
        }
        overrides.push_back("seed=" + std::string(v));
      } else {
        overrides.emplace_back(v);
      }
      continue;
    }
    if (!a.empty() && a.front() == '-') {
      std::fprintf(stderr, "cleanslam-sim: unknown option %s\n", argv[i]);
      usage(stderr);
      return 2;
    }
    positional.emplace_back(a);
  }
  if (positional.size() != 2) {
    usage(stderr);
    return 2;
  }
  auto scenario = sim::load_scenario(positional[0], overrides);
  if (!scenario.ok()) {
    std::fprintf(stderr, "cleanslam-sim: %s\n", scenario.error().c_str());
    return 1;
  }
  {
    namespace fs = std::filesystem;
    const fs::path out(positional[1]);
    std::error_code ec;
    if (fs::exists(out, ec) && !fs::is_empty(out, ec)) {
      if (!force) {
        std::fprintf(
            stderr,
            "cleanslam-sim: %s: folder is not empty (use --force to replace a dataset there)\n",
            positional[1].c_str());
        return 1;
      }
      for (const char* f :
           {"sensors.yaml", "gyro.csv", "encoders.csv", "features.csv", "groundtruth.csv",
            "sim_landmarks.csv", "sim_truth.yaml", "lift.csv", "cam0"}) {
        fs::remove_all(out / f, ec);
        if (ec) {
          std::fprintf(stderr, "cleanslam-sim: %s: cannot remove: %s\n", (out / f).c_str(),
                       ec.message().c_str());
          return 1;
        }
      }
    }
  }
  const bool tty = isatty(STDERR_FILENO) != 0;
  int last_percent = -1;
  // A counter on a terminal; else a line at every tenth.
  auto progress = [&](double f) {
    const int pct = tty ? static_cast<int>(f * 100.0) : static_cast<int>(f * 10.0) * 10;
    if (pct == last_percent) {
      return;
    }
    last_percent = pct;
    if (tty) {
      std::fprintf(stderr, "\rcleanslam-sim: %s %3d%%", scenario->name.c_str(), pct);
    } else {
      std::fprintf(stderr, "cleanslam-sim: %s %3d %%\n", scenario->name.c_str(), pct);
    }
    std::fflush(stderr);
  };
  auto result = sim::simulate(*scenario, positional[1], progress);
  if (tty) {
    std::fprintf(stderr, "\n");
  }
  if (!result.ok()) {
    std::fprintf(stderr, "cleanslam-sim: %s\n", result.error().c_str());
    return 1;
  }
  const auto& s = *result;
  std::fprintf(
      stderr,
      "cleanslam-sim: %s seed %llu -> %s\n"
      "  %.1f s, %.1f m of path, %d landmarks, %d frames (%d without features)\n"
      "  %.2f features per frame, %.0f%% of frames with 5-10 landmarks in view (%.0f%% with >= 5), "
      "longest gap without a landmark %.1f s, %d wheel slips\n",
      scenario->name.c_str(), static_cast<unsigned long long>(scenario->seed),
      positional[1].c_str(), s.duration_s, s.path_length_m, s.landmarks, s.frames,
      s.frames_without_features, s.mean_features, 100.0 * s.fraction_frames_5_to_10,
      100.0 * s.fraction_frames_5_or_more, s.longest_gap_s, s.slip_events);
  if (!s.images.empty()) {
    std::fprintf(stderr, "  images: %s\n", s.images.c_str());
  }
  return 0;
}
