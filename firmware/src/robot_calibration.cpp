#include "cleanslam/firmware/robot_calibration.hpp"

namespace cleanslam::firmware {

std::string uncalibrated_message(const std::vector<std::string>& keys_not_set,
                                 const std::string& config_path) {
  std::string keys;
  for (const std::string& k : keys_not_set) {
    keys += (keys.empty() ? "" : ", ") + k;
  }
  const std::string where = config_path.empty() ? std::string("the configuration") : config_path;
  return "uncalibrated: " + keys + (keys_not_set.size() == 1 ? " is" : " are") +
         " the sample's, not this robot's; health stays degraded (status LED blinking slowly) "
         "until they are measured with cleanslam-calibrate and set in the calibration section "
         "of " +
         where + " (docs/bring-up.md)";
}

}  // namespace cleanslam::firmware
