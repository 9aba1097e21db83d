#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cleanslam/firmware/config.hpp"

// The command line of `cleanslam`.
namespace cleanslam::firmware {

struct Args {
  std::string config_path;
  std::vector<std::string> sets;
  std::string replay_log;
  std::string replay_out;
  bool help = false;
  bool version = false;
  bool print_sample_config = false;
};

// The arguments, or nothing after a message on stderr.
std::optional<Args> parse_args(int argc, char** argv);
// What --help prints.
const char* usage_text();
// A configuration's warnings and errors, on stderr.
void print_messages(const ConfigResult& r);

}  // namespace cleanslam::firmware
