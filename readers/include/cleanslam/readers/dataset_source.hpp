#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/interfaces.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/gray_image.hpp"

namespace cleanslam::readers {

// A virtual-time hal::SensorSource over a dataset folder: gyro, encoder and frame events merged in
// time order (at equal stamps: gyro, then encoder, then lift, then frame); lift.csv (a format
// extension) gives kLift events. A frame is every distinct stamp
// of cam0/data.csv and features.csv; it carries the image of that stamp (loaded from disk when it
// is its turn, one image in memory at a time) and/or the features of that stamp (at most
// hal::kMaxFeaturesPerFrame; more are dropped with a warning at load). Frame stamps are the
// file's stamps; sensors.yaml's time_offset_s is left to the consumer unless
// apply_time_offset is set. Deterministic: the same folder gives the same events.
class DatasetSource final : public hal::SensorSource {
 public:
  struct Options {
    bool apply_time_offset = false;
    LoadOptions load;
  };

  static Result<DatasetSource> open(const std::string& folder, const Options& options);
  static Result<DatasetSource> open(const std::string& folder) { return open(folder, Options{}); }

  [[nodiscard]] hal::TimeNs next_event_time() const override;
  bool read(hal::SensorEvent& out) override;
  [[nodiscard]] bool exhausted() const override;

  [[nodiscard]] const Dataset& dataset() const { return dataset_; }
  [[nodiscard]] const hal::Calibration& calibration() const { return dataset_.calibration; }
  [[nodiscard]] const std::vector<std::string>& warnings() const { return dataset_.warnings; }
  // Images that failed to load while streaming (their frames went out without an image).
  [[nodiscard]] int image_errors() const { return image_errors_; }
  [[nodiscard]] const std::string& last_error() const { return last_error_; }
  [[nodiscard]] std::size_t frame_count() const { return frames_.size(); }

 private:
  struct FrameIndex {
    hal::TimeNs t_ns = 0;
    int camera_row = -1;  // index into dataset_.camera or -1
    std::size_t feature_begin = 0;
    int feature_count = 0;
  };

  Dataset dataset_;
  std::vector<FrameIndex> frames_;
  hal::TimeNs frame_offset_ns_ = 0;
  std::size_t next_gyro_ = 0;
  std::size_t next_encoder_ = 0;
  std::size_t next_frame_ = 0;
  std::size_t next_lift_ = 0;
  GrayImage image_;
  std::vector<hal::FeatureObservation> frame_features_;
  int image_errors_ = 0;
  std::string last_error_;
};

}  // namespace cleanslam::readers
