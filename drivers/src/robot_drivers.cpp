#include "cleanslam/drivers/robot_drivers.hpp"

namespace cleanslam::drivers {

RobotDrivers::RobotDrivers(const RobotDriversConfig& config, Os& os, GpioApi& gpio,
                           Diagnostics& diagnostics) {
  if (!config.gyro_ready.gpio.line.empty()) {
    gyro_ready_ = std::make_unique<GyroDataReady>(config.gyro_ready, gpio, os, diagnostics);
  }
  if (!config.can.interface.empty()) {
    base_board_ = std::make_unique<CanBaseBoard>(config.can, os, diagnostics);
    if (gyro_ready_ != nullptr && gyro_ready_->available()) {
      base_board_->set_gyro_time_reference(gyro_ready_.get());
    }
    sources_[static_cast<std::size_t>(count_++)] = base_board_.get();
  }
  if (!config.camera.device.empty()) {
    camera_ = std::make_unique<V4l2Camera>(config.camera, os, diagnostics);
    sources_[static_cast<std::size_t>(count_++)] = camera_.get();
  }
  if (!config.lift.gpio.line.empty()) {
    lift_ = std::make_unique<LiftSwitch>(config.lift, gpio, os, diagnostics);
    sources_[static_cast<std::size_t>(count_++)] = lift_.get();
  }
  if (!config.status_led.line.empty()) {
    led_ = std::make_unique<StatusLed>(config.status_led, gpio, diagnostics);
  }
  if (!config.pose_interface.empty()) {
    pose_sink_ = std::make_unique<CanPoseSink>(config.pose_interface, os, diagnostics);
  }
}

bool RobotDrivers::inputs_missing() const {
  return (lift_ != nullptr && !lift_->available()) ||
         (gyro_ready_ != nullptr && !gyro_ready_->available());
}

}  // namespace cleanslam::drivers
