#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/frame.hpp"
#include "cleanslam/hal/samples.hpp"
#include "cleanslam/readers/result.hpp"

// Readers and writers of the dataset folder format (docs/dataset-format.md). Readers refuse a
// file that does not follow the format with a message naming the file, line and field.
namespace cleanslam::readers {

// Pose of the body frame in the world frame (groundtruth.csv), quaternion normalized.
struct GroundTruthPose {
  hal::TimeNs t_ns = 0;
  std::array<double, 3> position_m{};
  std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};
};

struct CameraIndexRow {
  hal::TimeNs t_ns = 0;
  std::string filename;  // relative to cam0/data/
  int line = 0;          // in cam0/data.csv, for messages
};

// lift.csv (an extension of the format, optional): "#t_ns,lifted", one row per change of the
// wheel-drop state, 1 when the robot leaves the floor, 0 when it is set down.
struct LiftRow {
  hal::TimeNs t_ns = 0;
  bool lifted = false;
};

struct FeatureRow {
  hal::TimeNs t_ns = 0;
  hal::FeatureObservation observation;
};

// sensors.yaml. Unknown keys are appended to `warnings` (when given).
Result<hal::Calibration> read_sensors_yaml(const std::string& path,
                                           std::vector<std::string>* warnings = nullptr);
Result<hal::Calibration> parse_sensors_yaml(const std::string& text, const std::string& file_name,
                                            std::vector<std::string>* warnings = nullptr);
std::string sensors_yaml_text(const hal::Calibration& calibration);

// Time stamps must be strictly increasing (features.csv: non-decreasing).
Result<std::vector<hal::GyroSample>> read_gyro_csv(const std::string& path);
Result<std::vector<hal::EncoderSample>> read_encoders_csv(const std::string& path);
Result<std::vector<CameraIndexRow>> read_camera_csv(const std::string& path);
Result<std::vector<FeatureRow>> read_features_csv(const std::string& path);
Result<std::vector<GroundTruthPose>> read_groundtruth_csv(const std::string& path);
Result<std::vector<LiftRow>> read_lift_csv(const std::string& path);

// Everything of a dataset folder except the image pixels.
struct Dataset {
  std::string folder;
  hal::Calibration calibration;
  std::vector<hal::GyroSample> gyro;
  std::vector<hal::EncoderSample> encoders;
  std::vector<CameraIndexRow> camera;  // empty when there is no cam0/
  std::vector<FeatureRow> features;    // empty when there is no features.csv
  std::vector<GroundTruthPose> groundtruth;
  std::vector<LiftRow> lift;  // empty when there is no lift.csv
  bool has_camera = false;
  bool has_features = false;
  bool has_groundtruth = false;
  std::vector<std::string> warnings;

  [[nodiscard]] std::string image_path(const CameraIndexRow& row) const;
};

struct LoadOptions {
  // Check that every image exists and has the calibrated size (reads headers only).
  bool check_images = true;
};

// Reads and validates a dataset folder.
Result<Dataset> load_dataset(const std::string& folder, const LoadOptions& options = {});

// Shortest text that reads back as the same double.
std::string format_double(double v);

}  // namespace cleanslam::readers
