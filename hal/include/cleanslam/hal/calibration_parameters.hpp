#pragma once

#include <array>
#include <limits>
#include <span>

#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/calibration_limits.hpp"
#include "cleanslam/hal/parameter.hpp"

// The calibration's keys (the sensors.yaml schema of docs/dataset-format.md, and the firmware
// configuration's `calibration` section) with their ranges from calibration_limits. The camera's
// size, intrinsics and mount are checked together after reading (camera_geometry_errors,
// camera_mount_error): the intrinsics and the mount have no range of their own here.
namespace cleanslam::hal {

inline std::span<const Parameter<Calibration>> calibration_parameters() {
  namespace lim = calibration_limits;
  using P = Parameter<Calibration>;
  using C = Calibration;
  constexpr double kAny = std::numeric_limits<double>::max();
  static constexpr std::array kTable{
      P{"camera.width", [](C& c) { return parameter_field(c.camera.width); }, 320.0,
        lim::kImageWidthPx.lo, lim::kImageWidthPx.hi, false, "px",
        "the front end takes images of at most 320x240 pixels"},
      P{"camera.height", [](C& c) { return parameter_field(c.camera.height); }, 240.0,
        lim::kImageHeightPx.lo, lim::kImageHeightPx.hi, false, "px",
        "the front end takes images of at most 320x240 pixels"},
      P{"camera.fx", [](C& c) { return parameter_field(c.camera.fx); }, 280.0, -kAny, kAny, false,
        "px", "focal length: a field of view across the width of 10 to 150 degrees"},
      P{"camera.fy", [](C& c) { return parameter_field(c.camera.fy); }, 280.0, -kAny, kAny, false,
        "px", "focal length: a field of view across the height of 10 to 150 degrees"},
      P{"camera.cx", [](C& c) { return parameter_field(c.camera.cx); }, 159.5, -kAny, kAny, false,
        "px", "principal point, origin at the top-left pixel's centre: inside the image"},
      P{"camera.cy", [](C& c) { return parameter_field(c.camera.cy); }, 119.5, -kAny, kAny, false,
        "px", "principal point: inside the image"},
      P{"camera.distortion", [](C& c) { return numbers_field(c.camera.distortion); }, 0.0,
        lim::kDistortion.lo, lim::kDistortion.hi, lim::kDistortion.lo_open, "",
        "radial-tangential k1 k2 p1 p2"},
      P{"camera.T_body_cam", [](C& c) { return numbers_field(c.camera.T_body_cam); }, 0.0, -kAny,
        kAny, false, "",
        "camera optical frame (z forward, x right, y down) in the body frame, 4x4 row-major: a "
        "rotation and a translation within 10 m"},
      P{"camera.pixel_noise", [](C& c) { return parameter_field(c.camera.pixel_noise); }, 0.5,
        lim::kPixelNoisePx.lo, lim::kPixelNoisePx.hi, lim::kPixelNoisePx.lo_open, "px",
        "std. dev. of a feature position"},
      P{"camera.time_offset_s", [](C& c) { return parameter_field(c.camera.time_offset_s); }, 0.0,
        lim::kTimeOffsetS.lo, lim::kTimeOffsetS.hi, lim::kTimeOffsetS.lo_open, "s",
        "camera stamp + offset = the gyro and encoder clock"},
      P{"wheels.ticks_per_meter_left",
        [](C& c) { return parameter_field(c.wheels.ticks_per_meter_left); }, 4000.0,
        lim::kTicksPerMeter.lo, lim::kTicksPerMeter.hi, lim::kTicksPerMeter.lo_open, "1/m",
        "encoder ticks per metre of the left wheel: at least one a centimetre"},
      P{"wheels.ticks_per_meter_right",
        [](C& c) { return parameter_field(c.wheels.ticks_per_meter_right); }, 4000.0,
        lim::kTicksPerMeter.lo, lim::kTicksPerMeter.hi, lim::kTicksPerMeter.lo_open, "1/m",
        "encoder ticks per metre of the right wheel"},
      P{"wheels.wheel_base", [](C& c) { return parameter_field(c.wheels.wheel_base); }, 0.235,
        lim::kWheelBaseM.lo, lim::kWheelBaseM.hi, lim::kWheelBaseM.lo_open, "m",
        "between the wheels' contact points"},
      P{"wheels.distance_noise", [](C& c) { return parameter_field(c.wheels.distance_noise); },
        0.02, lim::kFraction.lo, lim::kFraction.hi, lim::kFraction.lo_open, "",
        "std. dev. of the travelled distance as a fraction of it"},
      P{"wheels.scale_error", [](C& c) { return parameter_field(c.wheels.scale_error); }, 0.0,
        lim::kFraction.lo, lim::kFraction.hi, lim::kFraction.lo_open, "",
        "std. dev. of the distance scale factor error, 0: not stated"},
      P{"gyro.noise_density", [](C& c) { return parameter_field(c.gyro.noise_density); }, 0.0005,
        lim::kNoiseDensity.lo, lim::kNoiseDensity.hi, lim::kNoiseDensity.lo_open, "rad/s/sqrt(Hz)",
        "the rate's white noise"},
      P{"gyro.bias_instability", [](C& c) { return parameter_field(c.gyro.bias_instability); },
        0.0001, lim::kGyroBias.lo, lim::kGyroBias.hi, lim::kGyroBias.lo_open, "rad/s",
        "the bias's wander"},
      P{"gyro.scale_error", [](C& c) { return parameter_field(c.gyro.scale_error); }, 0.0,
        lim::kFraction.lo, lim::kFraction.hi, lim::kFraction.lo_open, "",
        "std. dev. of the rate scale factor error, 0: not stated"},
      P{"gyro.bias_walk", [](C& c) { return parameter_field(c.gyro.bias_walk); }, 0.0,
        lim::kGyroBias.lo, lim::kGyroBias.hi, lim::kGyroBias.lo_open, "rad/s/sqrt(s)",
        "bias random walk, 0: not stated"},
  };
  return kTable;
}

}  // namespace cleanslam::hal
