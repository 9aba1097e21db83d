#include "program_args.hpp"

#include <cstdio>

namespace cleanslam::firmware {

namespace {

constexpr const char* kUsage =
    "usage: cleanslam [--config FILE] [--set key=value ...]\n"
    "                 [--dataset DIR | --log LOG] [--realtime] [--record LOG] [--tum FILE]\n"
    "       cleanslam --replay LOG [--replay-out FILE]\n"
    "       cleanslam --print-sample-config | --version | --help\n"
    "Runs the localization loop on the robot's drivers, a dataset folder or a recorded log.\n"
    "--replay feeds a recorded log back through the loop at its recorded iterations and checks\n"
    "that the outputs are reproduced bit for bit (exit 0), else names the first difference\n"
    "(exit 1). --dataset/--log/--realtime/--record/--tum are shorthands for --set source.kind=,\n"
    "source.path=, source.realtime=true, recorder.path=, sinks.tum=.\n"
    "--print-sample-config prints every key with its default, range and meaning\n"
    "(firmware/config/cleanslam.sample.yaml).\n";

}  // namespace

const char* usage_text() {
  return kUsage;
}

std::optional<Args> parse_args(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&](const char* name) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "cleanslam: %s needs a value\n", name);
        return nullptr;
      }
      return argv[++i];
    };
    const char* v = nullptr;
    if (arg == "--help" || arg == "-h") {
      a.help = true;
    } else if (arg == "--version") {
      a.version = true;
    } else if (arg == "--print-sample-config") {
      a.print_sample_config = true;
    } else if (arg == "--realtime") {
      a.sets.emplace_back("source.realtime=true");
    } else if (arg == "--config" || arg == "--set" || arg == "--replay" || arg == "--replay-out" ||
               arg == "--dataset" || arg == "--log" || arg == "--record" || arg == "--tum") {
      if ((v = value(arg.c_str())) == nullptr) {
        return std::nullopt;
      }
      if (arg == "--config") {
        a.config_path = v;
      } else if (arg == "--set") {
        a.sets.emplace_back(v);
      } else if (arg == "--replay") {
        a.replay_log = v;
      } else if (arg == "--replay-out") {
        a.replay_out = v;
      } else if (arg == "--dataset") {
        a.sets.emplace_back("source.kind=dataset");
        a.sets.emplace_back(std::string("source.path=\"") + v + "\"");
      } else if (arg == "--log") {
        a.sets.emplace_back("source.kind=log");
        a.sets.emplace_back(std::string("source.path=\"") + v + "\"");
      } else if (arg == "--record") {
        a.sets.emplace_back(std::string("recorder.path=\"") + v + "\"");
      } else {
        a.sets.emplace_back(std::string("sinks.tum=\"") + v + "\"");
      }
    } else {
      std::fprintf(stderr, "cleanslam: unknown argument %s\n%s", arg.c_str(), kUsage);
      return std::nullopt;
    }
  }
  return a;
}

void print_messages(const ConfigResult& r) {
  for (const auto& w : r.warnings) {
    std::fprintf(stderr, "cleanslam: warning: %s\n", w.c_str());
  }
  for (const auto& e : r.errors) {
    std::fprintf(stderr, "cleanslam: error: %s\n", e.c_str());
  }
}

}  // namespace cleanslam::firmware
