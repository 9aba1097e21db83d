#include "cleanslam/firmware/summary_words.hpp"

#include <array>
#include <cstring>
#include <utility>

namespace cleanslam::firmware {

const char* explain(hal::log::UpdateStatus s) {
  using S = hal::log::UpdateStatus;
  switch (s) {
    case S::kUpdated:
      return "observations fused into the filter";
    case S::kInitialized:
      return "new landmarks put on the map at their first sighting";
    case S::kGated:
      return "observations refused as outliers by the innovation gate or JCBB";
    case S::kRejected:
      return "observations not used: with images mostly landmarks the tracker searched for and "
             "did not find (occluded, changed appearance); else outside the image, non-finite, "
             "covariance not positive definite, or the map full";
    case S::kSkipped:
      return "frames without an update: too few inliers, or the robot standing still";
    case S::kNoSlot:
      return "new landmarks not mapped: the map is full (filter.max_landmarks)";
    case S::kMerged:
      return "landmarks mapped again and merged into their earlier entry";
    case S::kMergeGated:
      return "merges refused by their gate: the earlier entry was deleted";
    case S::kDepthBound:
      return "updates refused: they would move a landmark behind the camera or beyond "
             "filter.max_depth_m";
    case S::kBehindCamera:
      return "landmarks whose estimate lies behind the camera: not predicted in the image";
  }
  return "";
}

const char* explain(Reject r) {
  switch (r) {
    case Reject::kOutOfOrder:
      return "samples whose time stamp is not after the previous one of the same sensor";
    case Reject::kTimeJump:
      return "samples stamped too far behind or ahead of the loop's clock (LoopConfig's "
             "max_time_skew_ns, max_lead_ns), or past the run's span (loop.max_span_s)";
    case Reject::kNonFinite:
      return "samples with NaN or infinity";
    case Reject::kFrameRate:
      return "frames closer to the last one taken than loop.frame_rate_hz allows (by design)";
    case Reject::kFrameSuperseded:
      return "frames replaced by a newer one while the previous frame was still being processed";
    case Reject::kImageSize:
      return "frames whose image is not of the calibrated size (calibration.camera.width, "
             "height)";
    case Reject::kBadFrame:
      return "frames larger than the capacity, or with neither an image nor features";
    case Reject::kBadFeature:
      return "features non-finite or beyond the capacity of a frame";
    case Reject::kCorruptRecord:
      return "damaged or truncated log records";
    case Reject::kRecorderDropped:
      return "records the recorder dropped because its buffer was full";
    case Reject::kCount:
      break;
  }
  return "";
}

const char* explain_observation_reason(const char* reason) {
  static constexpr std::array<std::pair<const char*, const char*>, 10> kWords{{
      {"non_finite", "non-finite measurement or prediction"},
      {"out_of_image", "predicted outside the image"},
      {"behind_camera", "landmark estimate behind the camera"},
      {"gate", "innovation beyond the chi-square gate (filter.gate_chi2)"},
      {"parallel_ray", "ray parallel to the landmark's uncertainty: no information"},
      {"not_positive_definite", "innovation covariance not positive definite"},
      {"invalid_slot", "landmark slot not in the map"},
      {"over_capacity", "more observations than a frame holds"},
      {"depth_bound", "would move the landmark behind the camera or too far"},
      {"out_of_range", "measurement out of the sensor's range"},
  }};
  for (const auto& [key, words] : kWords) {
    if (std::strcmp(key, reason) == 0) {
      return words;
    }
  }
  return "";
}

}  // namespace cleanslam::firmware
