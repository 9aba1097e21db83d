#pragma once

#include <fstream>
#include <string>

#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/frame.hpp"
#include "cleanslam/hal/samples.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/result.hpp"

namespace cleanslam::sim_hal {

// Writes a dataset folder row by row. Rows must be added in time order per file; files that get
// no row are not created (except the required ones).
class DatasetWriter {
 public:
  enum class ImageFormat { kPng, kPgm };

  DatasetWriter() = default;
  DatasetWriter(const DatasetWriter&) = delete;
  DatasetWriter& operator=(const DatasetWriter&) = delete;

  // Creates the folder (and parents), sensors.yaml, gyro.csv and encoders.csv.
  readers::Status open(const std::string& folder, const hal::Calibration& calibration,
                       ImageFormat image_format = ImageFormat::kPng);
  void add_gyro(const hal::GyroSample& g);
  void add_encoder(const hal::EncoderSample& e);
  // Writes cam0/data/<t_ns>.png (or .pgm) and its row in cam0/data.csv.
  readers::Status add_image(hal::TimeNs t_ns, const hal::GrayImageView& image);
  void add_features(hal::TimeNs t_ns, const hal::FeatureObservation* features, int count);
  void add_groundtruth(const readers::GroundTruthPose& p);
  // lift.csv (format extension): a change of the wheel-drop state.
  void add_lift(const readers::LiftRow& l);
  // Flushes and closes every file; reports a write error on any of them.
  readers::Status close();

 private:
  readers::Status open_stream(std::ofstream& out, const std::string& relative, const char* header);

  std::string folder_;
  ImageFormat image_format_ = ImageFormat::kPng;
  std::ofstream gyro_;
  std::ofstream encoders_;
  std::ofstream camera_;
  std::ofstream features_;
  std::ofstream groundtruth_;
  std::ofstream lift_;
};

}  // namespace cleanslam::sim_hal
