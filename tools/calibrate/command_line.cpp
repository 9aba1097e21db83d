#include "command_line.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <utility>

namespace cleanslam::calibrate {

double CommandLine::number(const std::string& option, double fallback) {
  const auto it = values.find(option);
  if (it == values.end()) {
    return fallback;
  }
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || *end != '\0' || !std::isfinite(v)) {
    if (error.empty()) {
      error = option + ": expected a number, got \"" + it->second + "\"";
    }
    return fallback;
  }
  return v;
}

CommandLine parse_command_line(int argc, char** argv, int first,
                               std::vector<std::string> value_options,
                               std::vector<std::string> flag_options) {
  for (const char* o : {"--out", "--form", "--base"}) {
    value_options.emplace_back(o);
  }
  flag_options.emplace_back("--force");
  CommandLine line;
  auto known = [](const std::vector<std::string>& list, const std::string& a) {
    return std::find(list.begin(), list.end(), a) != list.end();
  };
  for (int i = first; i < argc; ++i) {
    const std::string a = argv[i];
    if (known(flag_options, a)) {
      line.flags.insert(a);
    } else if (known(value_options, a)) {
      if (i + 1 >= argc) {
        line.error = a + " needs a value";
        return line;
      }
      line.values[a] = argv[++i];
    } else if (!a.empty() && a.front() == '-') {
      line.error = "unknown option " + a;
      return line;
    } else {
      line.positional.push_back(a);
    }
  }
  const auto form = line.values.find("--form");
  if (form != line.values.end() && form->second != "calibration" && form->second != "sensors") {
    line.error = "--form: expected calibration or sensors, got \"" + form->second + "\"";
  }
  return line;
}

bool two_sizes(const std::string& text, int& a, int& b) {
  char tail = 0;
  return std::sscanf(text.c_str(), "%dx%d%c", &a, &b, &tail) == 2 && a > 0 && b > 0;
}

void read_board(CommandLine& line, Checkerboard& board) {
  board.square_m = line.number("--square", 0.0);
  if (!line.error.empty()) {
    return;
  }
  if (!line.has("--board") || !two_sizes(line.values.at("--board"), board.cols, board.rows)) {
    line.error = "--board: expected the inner corners as COLSxROWS, e.g. 9x6, got \"" +
                 (line.has("--board") ? line.values.at("--board") : std::string()) + "\"";
  } else if (!(board.square_m > 0.0)) {
    line.error = "--square METRES: the side of a square is needed (positive)";
  }
}

void tell(const char* command, const std::string& message) {
  std::fprintf(stderr, "cleanslam-calibrate %s: %s\n", command, message.c_str());
}

int emit(const char* program, const CommandLine& line, const CalibrationResult& result,
         const std::vector<std::string>& inputs) {
  std::string text;
  if (line.has("--base")) {
    auto full = sensors_yaml_with(line.values.at("--base"), result);
    if (!full.ok()) {
      std::fprintf(stderr, "%s: %s\n", program, full.error().c_str());
      return 1;
    }
    text = *full;
  } else {
    const bool sensors = line.has("--form") && line.values.at("--form") == "sensors";
    text =
        calibration_yaml_text(result, sensors ? YamlForm::kSensors : YamlForm::kCalibrationSection);
  }
  if (!line.has("--out")) {
    std::fputs(text.c_str(), stdout);
    return 0;
  }
  const std::string& out = line.values.at("--out");
  readers::Status s = write_calibration_file(out, text, line.flags.count("--force") > 0, inputs);
  if (!s) {
    std::fprintf(stderr, "%s: %s\n", program, s.error().c_str());
    return 1;
  }
  std::fprintf(stderr, "%s: wrote %s\n", program, out.c_str());
  return 0;
}

}  // namespace cleanslam::calibrate
