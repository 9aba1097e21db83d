#include "cleanslam/calibrate/sample_files.hpp"

#include <filesystem>
#include <system_error>

namespace cleanslam::calibrate {
namespace {

bool is_log(const readers::Dataset& recording) {
  std::error_code ec;
  return std::filesystem::is_regular_file(recording.folder, ec);
}

}  // namespace

std::string samples_file(const readers::Dataset& recording, Samples which) {
  const bool gyro = which == Samples::kGyro;
  if (is_log(recording)) {
    return recording.folder + (gyro ? " (its gyro records)" : " (its encoder records)");
  }
  return recording.folder + (gyro ? "/gyro.csv" : "/encoders.csv");
}

std::string sample_place(const readers::Dataset& recording, Samples which, std::size_t k) {
  if (is_log(recording)) {
    return std::string(which == Samples::kGyro ? "gyro" : "encoder") + " record " +
           std::to_string(k + 1);
  }
  return "line " + std::to_string(k + 2);
}

}  // namespace cleanslam::calibrate
