#include "cleanslam/firmware/status_indicator.hpp"

#include "cleanslam/hal/pose.hpp"

namespace cleanslam::firmware {

drivers::LedPattern led_pattern(std::uint32_t health, bool devices_missing) {
  if ((health & (hal::kPoseLost | hal::kLifted)) != 0) {
    return drivers::LedPattern::kFault;
  }
  if (devices_missing || (health & (hal::kGyroSilent | hal::kEncodersSilent | hal::kCameraSilent |
                                    hal::kFewLandmarks)) != 0) {
    return drivers::LedPattern::kDegraded;
  }
  return drivers::LedPattern::kOk;
}

}  // namespace cleanslam::firmware
