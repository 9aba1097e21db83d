#include "cleanslam/firmware/slam_config_from_firmware.hpp"

namespace cleanslam::firmware {

slam_core::SlamConfig slam_config(const FirmwareConfig& c) {
  slam_core::SlamConfig s = c.slam;
  s.odometry.gyro_timeout_s = hal::to_seconds(c.loop.gyro_timeout_ns);
  s.update_work_step = static_cast<std::int64_t>(c.loop.frame_work_budget) * kUpdateWorkPerUnit;
  return s;
}

}  // namespace cleanslam::firmware
