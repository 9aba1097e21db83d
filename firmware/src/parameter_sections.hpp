#pragma once

#include <string>
#include <vector>

#include "cleanslam/hal/calibration.hpp"

// The configuration's sections as the parameter tables lay them out: the keys of
// slam_core::slam_parameters() and firmware_parameters(), nested at their dots.
namespace cleanslam::firmware::parameter_sections {

// The mappings directly below `prefix` ("" gives the top-level sections), the estimator's first,
// each in its table's order.
std::vector<std::string> children(const std::string& prefix);

// "calibration:" and its camera, wheels and gyro mappings through hal::calibration_parameters();
// with `comments`, each key's meaning, unit and range.
void write_calibration(std::string& out, const hal::Calibration& calibration, bool comments);

}  // namespace cleanslam::firmware::parameter_sections
