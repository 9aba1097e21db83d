#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cleanslam/readers/result.hpp"

// Every reader of a file the user names opens it through here: a regular file only (a directory,
// a FIFO, a device such as /dev/zero or a socket is refused without reading it), of at most a
// stated size. The message names the file, what it is, and the constant that sets the limit.
// The robot's devices (V4L2, SocketCAN, GPIO) are opened by the drivers, never through here.
namespace cleanslam::readers {

struct FileLimit {
  std::uint64_t max_bytes;
  const char* name;  // the constant or key that sets max_bytes, named in the message
  const char* why;   // what the limit is about, e.g. "a configuration"
};

// A YAML document: the firmware's configuration, sensors.yaml, a simulator scenario.
inline constexpr FileLimit kYamlFileLimit{std::uint64_t{1} << 20, "readers::kYamlFileLimit",
                                          "a YAML document"};
// A dataset CSV (gyro.csv, encoders.csv, cam0/data.csv, features.csv, groundtruth.csv,
// lift.csv): a day of 100 Hz gyro rows is well below it.
inline constexpr FileLimit kCsvFileLimit{std::uint64_t{4} << 30, "readers::kCsvFileLimit",
                                         "a dataset CSV file"};
// One camera image (PNG or PGM) of a dataset.
inline constexpr FileLimit kImageFileLimit{std::uint64_t{16} << 20, "readers::kImageFileLimit",
                                           "an image"};
// A recorded log, which is read whole into memory: recorder.max_file_mb's default of 64 MB times
// recorder.max_files' default of 4, joined, is well below it.
inline constexpr FileLimit kLogFileLimit{std::uint64_t{1} << 30, "readers::kLogFileLimit",
                                         "a log (read whole)"};
// A TUM trajectory or its covariance side file, read whole by the evaluation.
inline constexpr FileLimit kTrajectoryFileLimit{
    std::uint64_t{1} << 30, "readers::kTrajectoryFileLimit", "a trajectory (read whole)"};

// "a directory", "a FIFO", "a character device", ... for a file type of st_mode.
const char* file_kind(unsigned mode);

// The path names a regular file of at most limit.max_bytes (followed through symbolic links).
// The error is "PATH: is a directory, not a regular file", "PATH: N bytes, more than the M bytes
// of NAME (WHY)" or "PATH: cannot open: STRERROR".
Status check_bounded_file(const std::string& path, FileLimit limit);

// The whole content of a regular file of at most limit.max_bytes; opening does not block on a
// FIFO, and a file that grows while it is read is refused at the limit.
Result<std::string> read_bounded_file(const std::string& path, FileLimit limit);
// The same, as bytes.
Result<std::vector<std::uint8_t>> read_bounded_bytes(const std::string& path, FileLimit limit);

}  // namespace cleanslam::readers
