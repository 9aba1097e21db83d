#pragma once

#include <optional>
#include <string>

#include "cleanslam/calibrate/views.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "command_line.hpp"

// What cleanslam-calibrate's subcommands read: a dataset folder or a folder of images, or a
// firmware log (a path that is a regular file) holding the same samples or frames.
namespace cleanslam::calibrate {

// A recording's gyro and encoder samples: a folder's gyro.csv, encoders.csv and (when there is
// one) sensors.yaml with the dataset readers, or a firmware log's records, saying so and what
// was refused; nullopt after telling why they cannot be read. Camera files are not needed.
std::optional<readers::Dataset> read_recording(const char* command, const std::string& path);

// The views most frames of a log are thinned to by default.
inline constexpr int kMaxLogViews = 40;
inline constexpr const char* kEveryUsage =
    "  --every N    of a log's frames with an image, use every N-th (default: the least\n"
    "               N that leaves at most 40)\n";

// The images of a folder (every one), or of a log's frames (--every N, read from `line`);
// says how many are used; nullopt after telling why there are none.
std::optional<Views> read_views(const char* command, CommandLine& line, const std::string& path);

}  // namespace cleanslam::calibrate
