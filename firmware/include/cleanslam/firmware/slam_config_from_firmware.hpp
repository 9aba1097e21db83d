#pragma once

#include <cstdint>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/slam_core/slam_config.hpp"

namespace cleanslam::firmware {

// One loop.frame_work_budget unit of the EKF's batch update (Ekf::set_update_step), about one
// host instruction each.
inline constexpr std::int64_t kUpdateWorkPerUnit = 32768;

// The estimator's configuration from the firmware's filter, frontend, robot and loop settings.
slam_core::SlamConfig slam_config(const FirmwareConfig& c);

}  // namespace cleanslam::firmware
