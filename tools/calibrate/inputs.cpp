#include "inputs.hpp"

#include <filesystem>
#include <system_error>
#include <utility>
#include <vector>

#include "cleanslam/calibrate/camera_calibration.hpp"
#include "cleanslam/calibrate/log_recording.hpp"

namespace cleanslam::calibrate {
namespace {

bool is_log(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

void tell_all(const char* command, const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) {
    tell(command, "warning: " + w);
  }
}

std::optional<readers::Dataset> read_log_recording(const char* command, const std::string& path) {
  tell(command, "reading the gyro and encoder records of the log " + path);
  std::vector<std::string> warnings;
  auto d = read_log_samples(path, warnings);
  tell_all(command, warnings);
  if (!d.ok()) {
    tell(command, d.error());
    return std::nullopt;
  }
  tell(command, std::to_string(d->gyro.size()) + " gyro and " + std::to_string(d->encoders.size()) +
                    " encoder samples");
  return std::move(*d);
}

}  // namespace

std::optional<readers::Dataset> read_recording(const char* command, const std::string& path) {
  if (is_log(path)) {
    return read_log_recording(command, path);
  }
  const std::string& folder = path;
  tell(command, "reading " + folder);
  readers::Dataset d;
  d.folder = folder;
  auto gyro = readers::read_gyro_csv(folder + "/gyro.csv");
  if (!gyro.ok()) {
    tell(command, gyro.error());
    return std::nullopt;
  }
  d.gyro = std::move(*gyro);
  auto encoders = readers::read_encoders_csv(folder + "/encoders.csv");
  if (!encoders.ok()) {
    tell(command, encoders.error());
    return std::nullopt;
  }
  d.encoders = std::move(*encoders);
  // sensors.yaml is optional here: its wheel base, when there is one, only starts the wheels'
  // calculation.
  const std::string sensors = folder + "/sensors.yaml";
  if (std::filesystem::exists(sensors)) {
    auto calibration = readers::read_sensors_yaml(sensors);
    if (!calibration.ok()) {
      tell(command, calibration.error());
      return std::nullopt;
    }
    d.calibration = *calibration;
  }
  return d;
}

std::optional<Views> read_views(const char* command, CommandLine& line, const std::string& path) {
  const int every = static_cast<int>(line.number("--every", 0.0));
  if (!line.error.empty() || (line.has("--every") && every < 1)) {
    tell(command, line.error.empty() ? "--every: expected a positive whole number, got \"" +
                                           line.values.at("--every") + "\""
                                     : line.error);
    return std::nullopt;
  }
  if (!is_log(path)) {
    Views v{image_files(path), {}};
    if (v.empty()) {
      tell(command, path + ": no images (png, jpg, jpeg, pgm, bmp)");
      return std::nullopt;
    }
    if (line.has("--every")) {
      tell(command, "warning: --every thins a log's frames only");
    }
    tell(command, std::to_string(v.size()) + " images in " + path);
    return v;
  }
  std::vector<std::string> warnings;
  auto frames = read_log_frames(path, every, kMaxLogViews, warnings);
  tell_all(command, warnings);
  if (!frames.ok()) {
    tell(command, frames.error());
    return std::nullopt;
  }
  tell(command, path + ": " + std::to_string(frames->views.size()) + " of its " +
                    std::to_string(frames->frames_with_image) +
                    " frames with an image used (--every " + std::to_string(frames->every) + "; " +
                    std::to_string(frames->frame_records) + " frame records)");
  return std::move(frames->views);
}

}  // namespace cleanslam::calibrate
