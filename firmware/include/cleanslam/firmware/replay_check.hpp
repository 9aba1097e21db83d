#pragma once

#include <cstddef>
#include <string>

#include "cleanslam/readers/log_source.hpp"

namespace cleanslam::firmware {

// Output records (poses, update diagnostics) of a log and of its replay, compared bit for bit.
struct OutputComparison {
  bool identical = false;
  std::size_t original_outputs = 0;
  std::size_t replayed_outputs = 0;
  std::size_t first_difference = 0;  // index among the output records, when not identical
  std::size_t original_offset = 0;   // file offset of that record in the original (if any)
  std::string description;           // what differs, for the report
};

// With `original_truncated`, a replay may go on past the last output that survived the cut (the
// outputs of the last recorded iteration may be missing from the original).
OutputComparison compare_outputs(const readers::LogReader& original,
                                 const readers::LogReader& replayed,
                                 bool original_truncated = false);

}  // namespace cleanslam::firmware
