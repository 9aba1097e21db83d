#include "cleanslam/firmware/status_indicator.hpp"

#include "cleanslam/hal/pose.hpp"

namespace cleanslam::firmware {

drivers::LedPattern led_pattern(std::uint32_t health, bool set_up_incomplete) {
  if ((health & (hal::kPoseLost | hal::kLifted)) != 0) {
    return drivers::LedPattern::kFault;
  }
  if (set_up_incomplete || (health & (hal::kGyroSilent | hal::kEncodersSilent | hal::kCameraSilent |
                                      hal::kFewLandmarks)) != 0) {
    return drivers::LedPattern::kDegraded;
  }
  return drivers::LedPattern::kOk;
}

}  // namespace cleanslam::firmware
