#pragma once

#include <string>

// Numbers in messages and YAML comments.
namespace cleanslam::calibrate {

std::string fixed(double v, int decimals);      // "%.*f"
std::string significant(double v, int digits);  // "%.*g"

}  // namespace cleanslam::calibrate
