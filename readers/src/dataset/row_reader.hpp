#pragma once

#include <cstddef>
#include <string>

#include "cleanslam/hal/time.hpp"
#include "cleanslam/readers/csv.hpp"
#include "cleanslam/readers/dataset.hpp"

namespace cleanslam::readers {

// The rows of one dataset CSV file (Row: hal::GyroSample, hal::EncoderSample, CameraIndexRow,
// FeatureRow, GroundTruthPose or LiftRow), read one at a time with every check of the format:
// the header, sorted stamps, the span limit (RowLimits), each field's value. Holds one row.
template <typename Row>
class RowReader {
 public:
  Status open(const std::string& path, const RowLimits& limits);
  // The next row kept, in `out`; false at the end of the file or at an error (error() not empty).
  bool next(Row& out);
  [[nodiscard]] const std::string& error() const { return error_; }

 private:
  // Rows stamped past the span are refused and told, at most kMaxTold times a file.
  bool within_span(const CsvRow& row, hal::TimeNs t);
  static constexpr int kMaxTold = 3;

  CsvReader csv_;
  RowLimits limits_;
  hal::TimeNs previous_ = 0;
  hal::TimeNs span_end_ = 0;
  std::size_t kept_ = 0;
  int told_ = 0;
  std::string error_;
};

}  // namespace cleanslam::readers
