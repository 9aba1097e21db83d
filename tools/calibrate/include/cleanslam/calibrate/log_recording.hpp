#pragma once

#include <string>
#include <vector>

#include "cleanslam/calibrate/views.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/result.hpp"

// A firmware log (cleanslam --record, hal/log_format.hpp) as a calibration recording: the inputs
// that crossed the hal boundary, read with readers::LogReader and readers::LogSource.
namespace cleanslam::calibrate {

// The gyro and encoder samples, each in time order; `folder` is the log's path (messages name
// it), the calibration is left at its defaults (the log holds the firmware's configuration, not a
// sensors.yaml). `warnings`: records refused (damaged, implausible stamps) and a later file of a
// rotated recording. Refused, naming the file, when it is not a log or holds no gyro or encoder
// sample.
readers::Result<readers::Dataset> read_log_samples(const std::string& path,
                                                   std::vector<std::string>& warnings);

struct LogFrames {
  Views views;                // the kept frames' images, named "LOG: frame SEQ at T s"
  int frame_records = 0;      // frames in the log
  int frames_with_image = 0;  // of which carry an image (others: features only)
  int every = 1;              // every `every`-th frame with an image was kept
};

// The images of the log's frames, every `every`-th of those with one, from the first; `every` 0:
// the least that keeps at most `max_views`. Refused, naming the file, when it is not a log or no
// frame has an image (the recorder keeps every recorder.frame_every-th frame, and a front end may
// give features only).
readers::Result<LogFrames> read_log_frames(const std::string& path, int every, int max_views,
                                           std::vector<std::string>& warnings);

}  // namespace cleanslam::calibrate
