#pragma once

#include <span>
#include <string_view>

#include "cleanslam/hal/parameter.hpp"
#include "cleanslam/slam_core/slam_config.hpp"

// Every setting of the estimator once (hal/parameter.hpp): its configuration key, the member of
// SlamConfig it sets, its default, range, unit and meaning.
namespace cleanslam::slam_core {

// Every key of SlamConfig a configuration sets, in the order of the sample configuration.
// Members set from elsewhere are not listed: the image size (the camera calibration), the gyro
// timeout (the firmware's loop.gyro_timeout_s).
std::span<const hal::Parameter<SlamConfig>> slam_parameters();

// The key's entry, or nullptr.
const hal::Parameter<SlamConfig>* find_slam_parameter(std::string_view key);

}  // namespace cleanslam::slam_core
