#pragma once

#include <array>
#include <string>
#include <vector>

namespace cleanslam::firmware {

// The calibration keys that describe one robot and are measured on it (docs/bring-up.md); the
// other calibration keys are noise figures of the sensors' kind. A robot whose configuration
// leaves one of these out runs on the sample's value for it.
inline constexpr std::array<const char*, 10> kMeasuredCalibrationKeys = {
    "calibration.camera.fx",
    "calibration.camera.fy",
    "calibration.camera.cx",
    "calibration.camera.cy",
    "calibration.camera.distortion",
    "calibration.camera.T_body_cam",
    "calibration.wheels.ticks_per_meter_left",
    "calibration.wheels.ticks_per_meter_right",
    "calibration.wheels.wheel_base",
    "calibration.gyro.noise_density",
};

// What the firmware says when it runs on the robot with `keys_not_set` (of
// kMeasuredCalibrationKeys) left at the sample's values: the keys, the tool that measures them and
// where they go.
std::string uncalibrated_message(const std::vector<std::string>& keys_not_set,
                                 const std::string& config_path);

}  // namespace cleanslam::firmware
