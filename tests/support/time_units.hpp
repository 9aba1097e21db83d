#pragma once

#include "cleanslam/hal/time.hpp"

// Time units of the tests' scripted sensor streams; one definition, so that test files compiled
// together in a unity build agree on them.
namespace cleanslam::test {

inline constexpr hal::TimeNs kMs = hal::kNsPerMillisecond;
inline constexpr hal::TimeNs kS = hal::kNsPerSecond;

}  // namespace cleanslam::test
