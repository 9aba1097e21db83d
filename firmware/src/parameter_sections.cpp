#include "parameter_sections.hpp"

#include "cleanslam/firmware/firmware_parameters.hpp"
#include "cleanslam/readers/parameter_yaml.hpp"
#include "cleanslam/slam_core/parameter_table.hpp"

namespace cleanslam::firmware::parameter_sections {

std::vector<std::string> children(const std::string& prefix) {
  std::vector<std::string> out;
  readers::parameter_children(slam_core::slam_parameters(), prefix, out);
  readers::parameter_children(firmware_parameters(), prefix, out);
  return out;
}

}  // namespace cleanslam::firmware::parameter_sections
