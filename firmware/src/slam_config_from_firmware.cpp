#include "cleanslam/firmware/slam_config_from_firmware.hpp"

namespace cleanslam::firmware {

slam_core::SlamConfig slam_config(const FirmwareConfig& c) {
  slam_core::SlamConfig s = c.slam;
  s.odometry.gyro_timeout_s = hal::to_seconds(c.loop.gyro_timeout_ns);
  slam_core::MapConfig& m = s.map;
  m.on_set_down = c.robot.on_set_down == RobotSettings::SetDown::kRelocalize
                      ? slam_core::MapConfig::SetDown::kRelocalize
                      : slam_core::MapConfig::SetDown::kNewMap;
  m.relocalize_std_m = c.robot.relocalize_std_m;
  m.relocalize_std_yaw_deg = c.robot.relocalize_std_yaw_deg;
  s.gyro_errors_from_calibration = c.gyro_errors_from_calibration;
  s.update_work_step = static_cast<std::int64_t>(c.loop.frame_work_budget) * kUpdateWorkPerUnit;
  return s;
}

}  // namespace cleanslam::firmware
