#pragma once

#include <array>
#include <memory>
#include <string>

#include "cleanslam/drivers/can_base_board.hpp"
#include "cleanslam/drivers/can_pose_sink.hpp"
#include "cleanslam/drivers/gyro_data_ready.hpp"
#include "cleanslam/drivers/lift_switch.hpp"
#include "cleanslam/drivers/status_led.hpp"
#include "cleanslam/drivers/v4l2_camera.hpp"

namespace cleanslam::drivers {

// Everything the robot's firmware needs from drivers/, configured in one place. An empty
// camera device, interface or line leaves that part out.
struct RobotDriversConfig {
  CanBaseBoardConfig can;          // interface "" : no base board
  V4l2CameraConfig camera;         // device "" : no camera
  LiftSwitchConfig lift;           // gpio.line "" : no lift switch
  GpioLineConfig status_led;       // line "" : no LED
  GyroDataReadyConfig gyro_ready;  // gpio.line "" : CAN reception times for the gyro
  std::string pose_interface;      // "" : poses not sent on CAN
};

// Owns the driver objects; the loop polls sources() and publishes to pose_sink().
class RobotDrivers {
 public:
  explicit RobotDrivers(const RobotDriversConfig& config, Os& os = linux_os(),
                        GpioApi& gpio = libgpiod_api(),
                        Diagnostics& diagnostics = stderr_diagnostics());

  // The sensor sources present, in a fixed order (base board, camera, lift); count() of them.
  [[nodiscard]] hal::SensorSource* const* sources() const { return sources_.data(); }
  [[nodiscard]] int source_count() const { return count_; }
  [[nodiscard]] hal::PoseSink* pose_sink() const { return pose_sink_.get(); }
  [[nodiscard]] StatusLed* status_led() const { return led_.get(); }
  [[nodiscard]] CanBaseBoard* base_board() const { return base_board_.get(); }
  [[nodiscard]] V4l2Camera* camera() const { return camera_.get(); }
  [[nodiscard]] LiftSwitch* lift() const { return lift_.get(); }
  [[nodiscard]] GyroDataReady* gyro_ready() const { return gyro_ready_.get(); }
  // A configured GPIO input (lift switch, gyro data-ready) could not be had; the firmware runs
  // without it. (A missing camera or CAN interface shows as the source's silence.)
  [[nodiscard]] bool inputs_missing() const;

 private:
  std::unique_ptr<GyroDataReady> gyro_ready_;
  std::unique_ptr<CanBaseBoard> base_board_;
  std::unique_ptr<V4l2Camera> camera_;
  std::unique_ptr<LiftSwitch> lift_;
  std::unique_ptr<StatusLed> led_;
  std::unique_ptr<CanPoseSink> pose_sink_;
  std::array<hal::SensorSource*, 3> sources_{};
  int count_ = 0;
};

}  // namespace cleanslam::drivers
