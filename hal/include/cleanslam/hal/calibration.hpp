#pragma once

#include <array>

namespace cleanslam::hal {

// The sensors.yaml schema of docs/dataset-format.md, in SI units.
struct CameraCalibration {
  int width = 320;
  int height = 240;
  double fx = 280.0;
  double fy = 280.0;
  double cx = 159.5;
  double cy = 119.5;
  std::array<double, 4> distortion{};  // radial-tangential k1 k2 p1 p2
  // Camera optical frame (z forward, x right, y down) in the body frame, 4x4 row-major.
  std::array<double, 16> T_body_cam{0.0,  0.0,  1.0, 0.10,  //
                                    -1.0, 0.0,  0.0, 0.0,   //
                                    0.0,  -1.0, 0.0, 0.08,  //
                                    0.0,  0.0,  0.0, 1.0};
  double pixel_noise = 0.5;
  double time_offset_s = 0.0;
};

struct WheelCalibration {
  double ticks_per_meter_left = 4000.0;
  double ticks_per_meter_right = 4000.0;
  double wheel_base = 0.235;
  double distance_noise = 0.02;
  double scale_error = 0.0;  // std. dev. of the distance scale factor error, 0: not stated
};

struct GyroCalibration {
  double noise_density = 0.0005;
  double bias_instability = 0.0001;
  double scale_error = 0.0;  // std. dev. of the rate scale factor error, 0: not stated
  double bias_walk = 0.0;    // bias random walk, rad/s/sqrt(s), 0: not stated
};

struct Calibration {
  CameraCalibration camera;
  WheelCalibration wheels;
  GyroCalibration gyro;
};

}  // namespace cleanslam::hal
