#pragma once

#include <cstdio>

#include "cleanslam/firmware/recorder.hpp"
#include "cleanslam/firmware/sinks.hpp"

namespace cleanslam::firmware {

// The outputs of a run once it ended: each is closed, and a write that failed is told as an error
// naming the file and the reason; a rotation is told with the key that bounds it. Any of them may
// be null (not configured). True when every output was written completely.
bool close_and_report_outputs(const char* program, TumWriter* tum, CsvSink* diagnostics,
                              Recorder* recorder, std::FILE* out);

}  // namespace cleanslam::firmware
