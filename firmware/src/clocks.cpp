#include "cleanslam/firmware/clocks.hpp"

#include <time.h>

namespace cleanslam::firmware {

hal::TimeNs MonotonicClock::now() const {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<hal::TimeNs>(ts.tv_sec) * hal::kNsPerSecond + ts.tv_nsec;
}

}  // namespace cleanslam::firmware
