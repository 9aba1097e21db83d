#pragma once

#include <cstddef>
#include <string>

#include "cleanslam/readers/dataset.hpp"

// For messages: where a recording's gyro or encoder samples came from. A dataset folder's
// FOLDER/gyro.csv and FOLDER/encoders.csv, or a firmware log's gyro and encoder records (the
// recording's `folder` is then the log file).
namespace cleanslam::calibrate {

enum class Samples { kGyro, kEncoders };

// "FOLDER/gyro.csv", or "LOG (its gyro records)".
std::string samples_file(const readers::Dataset& recording, Samples which);
// Where the k-th sample (from 0) is: "line N" of the CSV file (after its header), or "record N"
// (from 1) of that kind in the log.
std::string sample_place(const readers::Dataset& recording, Samples which, std::size_t k);

}  // namespace cleanslam::calibrate
