#pragma once

#include <functional>
#include <string>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/gray_image.hpp"

namespace cleanslam::readers {

enum class DatasetFile { kGyro, kEncoders, kCamera, kFeatures, kLift, kGroundTruth };
// The path of one of a dataset folder's files.
std::string dataset_file(const std::string& folder, DatasetFile file);
// The path of the image of a row of cam0/data.csv.
std::string image_path(const std::string& folder, const CameraIndexRow& row);
// Reads the image of a row: refused when its path (through symbolic links) leads out of the
// dataset folder, when it is not a regular file, and as read_gray_image refuses it.
Status read_dataset_image(const std::string& folder, const std::string& path, GrayImage& out);
// The size of the image of a row, refused as read_dataset_image refuses it.
Result<ImageSize> read_dataset_image_size(const std::string& folder, const std::string& path);

// What to do with each row of a dataset folder's files; an empty function skips the rows.
struct RowVisitors {
  std::function<void(const hal::GyroSample&)> gyro;
  std::function<void(const hal::EncoderSample&)> encoders;
  std::function<void(const CameraIndexRow&)> camera;
  std::function<void(const FeatureRow&)> features;
  std::function<void(const LiftRow&)> lift;
  std::function<void(const GroundTruthPose&)> groundtruth;
};

// Reads and checks every file of a dataset folder, one row at a time, handing each row to its
// visitor. `out` receives everything but the rows (the visitors may fill them). Stops at the first
// error: sensors.yaml, gyro.csv, encoders.csv, cam0/data.csv, its images, features.csv, lift.csv,
// groundtruth.csv, in this order.
Status scan_dataset(const std::string& folder, const LoadOptions& options, const RowVisitors& visit,
                    Dataset& out);

}  // namespace cleanslam::readers
