#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "cleanslam/calibrate/calibration_yaml.hpp"
#include "cleanslam/calibrate/camera_calibration.hpp"

// The command line shared by cleanslam-calibrate's subcommands: positional arguments, options
// with a value, flags, and the output options every subcommand takes.
namespace cleanslam::calibrate {

struct CommandLine {
  std::vector<std::string> positional;
  std::map<std::string, std::string> values;
  std::set<std::string> flags;
  std::string error;  // set when the line does not parse

  [[nodiscard]] bool has(const std::string& option) const { return values.count(option) > 0; }
  // The option's number, or `fallback` when absent; sets `error` (naming the option and the
  // value) when it is not a finite number.
  double number(const std::string& option, double fallback);
};

// `value_options` take a value, `flag_options` none; --out, --form, --base and --force are added.
CommandLine parse_command_line(int argc, char** argv, int first,
                               std::vector<std::string> value_options,
                               std::vector<std::string> flag_options);

inline constexpr const char* kOutputUsage =
    "  --out FILE   write the measured keys as YAML (default: print them)\n"
    "  --form F     calibration (default): under `calibration:`, for the firmware's\n"
    "               configuration; sensors: at the top level, as in a dataset's sensors.yaml\n"
    "  --base FILE  write a complete sensors.yaml: FILE's with the measured keys replaced\n"
    "  --force      replace an existing --out file\n";

// "9x6" into its two numbers; false when it is not two positive integers.
bool two_sizes(const std::string& text, int& a, int& b);
// --board COLSxROWS and --square METRES into `board`; sets the line's error (naming the option and
// the value) when either is absent or malformed.
void read_board(CommandLine& line, Checkerboard& board);

// Prints "cleanslam-calibrate COMMAND: message" on stderr.
void tell(const char* command, const std::string& message);

// Prints or writes the result as the output options say; returns the exit status.
int emit(const char* program, const CommandLine& line, const CalibrationResult& result,
         const std::vector<std::string>& inputs);

}  // namespace cleanslam::calibrate
