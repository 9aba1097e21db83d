#pragma once

#include <span>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/hal/parameter.hpp"

// The firmware's own keys (hal/parameter.hpp): the loop, the sources, the outputs, the recorder,
// the robot's wiring and the map file, each once with its default, range, unit and meaning.
namespace cleanslam::firmware {

// In the order of the sample configuration.
std::span<const hal::Parameter<FirmwareConfig>> firmware_parameters();

}  // namespace cleanslam::firmware
