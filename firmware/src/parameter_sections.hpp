#pragma once

#include <string>
#include <vector>

// The configuration's sections as the parameter tables lay them out: the keys of
// slam_core::slam_parameters() and firmware_parameters(), nested at their dots.
namespace cleanslam::firmware::parameter_sections {

// The mappings directly below `prefix` ("" gives the top-level sections), the estimator's first,
// each in its table's order.
std::vector<std::string> children(const std::string& prefix);

}  // namespace cleanslam::firmware::parameter_sections
