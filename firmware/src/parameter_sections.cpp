#include "parameter_sections.hpp"

#include "cleanslam/firmware/firmware_parameters.hpp"
#include "cleanslam/hal/calibration_parameters.hpp"
#include "cleanslam/readers/parameter_yaml.hpp"
#include "cleanslam/slam_core/parameter_table.hpp"

namespace cleanslam::firmware::parameter_sections {

std::vector<std::string> children(const std::string& prefix) {
  std::vector<std::string> out;
  readers::parameter_children(slam_core::slam_parameters(), prefix, out);
  readers::parameter_children(firmware_parameters(), prefix, out);
  return out;
}

void write_calibration(std::string& out, const hal::Calibration& calibration, bool comments) {
  out += "calibration:\n";
  for (const char* group : {"camera", "wheels", "gyro"}) {
    out.append("  ").append(group).append(":\n");
    readers::write_parameters(out, hal::calibration_parameters(), std::string(group) + ".", "    ",
                              calibration, comments);
  }
}

}  // namespace cleanslam::firmware::parameter_sections
