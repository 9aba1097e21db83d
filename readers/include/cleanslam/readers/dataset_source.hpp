#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/interfaces.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/gray_image.hpp"

namespace cleanslam::readers {

// What DatasetSource::open learned of a dataset folder; the rows themselves are not kept.
struct DatasetSummary {
  std::string folder;
  hal::Calibration calibration;
  bool has_camera = false;
  bool has_features = false;
  std::vector<std::string> warnings;
  std::uint64_t rows_refused = 0;  // stamped past the span (RowLimits)
  // First and last stamp of gyro.csv and encoders.csv together; -1 when both are empty.
  hal::TimeNs first_ns = -1;
  hal::TimeNs last_ns = -1;
  std::size_t frames = 0;
};

// A virtual-time hal::SensorSource over a dataset folder: gyro, encoder and frame events merged in
// time order (at equal stamps: gyro, then encoder, then lift, then frame); lift.csv (a format
// extension) gives kLift events. A frame is every distinct stamp of cam0/data.csv and
// features.csv; it carries the image of that stamp (loaded from disk when it is its turn, one
// image in memory at a time) and/or the features of that stamp (at most
// hal::kMaxFeaturesPerFrame; more are dropped with a warning at open). Frame stamps are the file's
// stamps; sensors.yaml's time_offset_s is left to the consumer unless apply_time_offset is set.
// Deterministic: the same folder gives the same events.
//
// open() reads and checks every file as load_dataset does, keeping no rows; the events are then
// read from the files as they fall due, one row of each file ahead: memory does not grow with the
// dataset's length.
class DatasetSource final : public hal::SensorSource {
 public:
  struct Options {
    bool apply_time_offset = false;
    LoadOptions load;
  };

  static Result<DatasetSource> open(const std::string& folder, const Options& options);
  static Result<DatasetSource> open(const std::string& folder) { return open(folder, Options{}); }

  DatasetSource(DatasetSource&&) noexcept;
  DatasetSource& operator=(DatasetSource&&) noexcept;
  ~DatasetSource() override;

  [[nodiscard]] hal::TimeNs next_event_time() const override;
  bool read(hal::SensorEvent& out) override;
  [[nodiscard]] bool exhausted() const override;

  [[nodiscard]] const DatasetSummary& summary() const { return summary_; }
  [[nodiscard]] const hal::Calibration& calibration() const { return summary_.calibration; }
  [[nodiscard]] const std::vector<std::string>& warnings() const { return summary_.warnings; }
  // Images that failed to load while streaming (their frames went out without an image), and
  // the messages of the first kMaxImageErrorsTold, each naming its file and cam0/data.csv line.
  static constexpr int kMaxImageErrorsTold = 5;
  [[nodiscard]] int image_errors() const { return image_errors_; }
  [[nodiscard]] const std::string& last_error() const { return last_error_; }
  [[nodiscard]] const std::vector<std::string>& image_error_messages() const {
    return image_error_messages_;
  }
  [[nodiscard]] std::size_t frame_count() const { return summary_.frames; }
  // A file changed after open() so that it no longer reads (a row out of order, a bad value, the
  // file gone): every stream ends at that row, and this names the file and line. Empty otherwise.
  [[nodiscard]] const std::string& stream_error() const;

 private:
  struct Streams;
  DatasetSource();

  DatasetSummary summary_;
  hal::TimeNs frame_offset_ns_ = 0;
  std::unique_ptr<Streams> streams_;
  std::size_t next_frame_ = 0;
  CameraIndexRow camera_row_;
  GrayImage image_;
  std::vector<hal::FeatureObservation> frame_features_;
  int image_errors_ = 0;
  std::string last_error_;
  std::vector<std::string> image_error_messages_;
};

}  // namespace cleanslam::readers
