#include "cleanslam/firmware/health.hpp"

#include <numeric>

namespace cleanslam::firmware {

const char* to_string(Reject r) {
  switch (r) {
    case Reject::kOutOfOrder:
      return "out_of_order";
    case Reject::kTimeJump:
      return "time_jump";
    case Reject::kNonFinite:
      return "non_finite";
    case Reject::kFrameRate:
      return "frame_rate";
    case Reject::kFrameSuperseded:
      return "frame_superseded";
    case Reject::kBadFrame:
      return "bad_frame";
    case Reject::kImageSize:
      return "image_size";
    case Reject::kBadFeature:
      return "bad_feature";
    case Reject::kCorruptRecord:
      return "corrupt_record";
    case Reject::kRecorderDropped:
      return "recorder_dropped";
    case Reject::kCount:
      break;
  }
  return "?";
}

std::uint64_t RejectCounters::total() const {
  return std::accumulate(n.begin(), n.end(), std::uint64_t{0});
}

}  // namespace cleanslam::firmware
