#pragma once

#include "cleanslam/firmware/health.hpp"
#include "cleanslam/hal/log_format.hpp"

namespace cleanslam::firmware {

// What the run summary's counters mean, in words a first-time user can read.
const char* explain(hal::log::UpdateStatus s);
const char* explain(Reject r);
// The filter's reasons for not fusing a measurement (ObservationRejection::reason); "" if unknown.
const char* explain_observation_reason(const char* reason);

}  // namespace cleanslam::firmware
