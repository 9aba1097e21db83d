#pragma once

#include <array>
#include <cmath>

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

// The camera is mounted on the robot: its offset from the body's origin is at most this.
inline constexpr double kMaxCameraOffsetM = 10.0;

// Why t is not a camera mount (a rigid transform, right-handed, within kMaxCameraOffsetM of the
// body's origin, finite), or nullptr when it is one.
[[nodiscard]] inline const char* camera_mount_error(const std::array<double, 16>& t) {
  for (const double v : t) {
    if (!std::isfinite(v)) {
      return "an entry is not finite";
    }
  }
  if (t[12] != 0.0 || t[13] != 0.0 || t[14] != 0.0 || t[15] != 1.0) {
    return "last row must be 0 0 0 1";
  }
  constexpr double kTol = 1e-4;
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      double dot = 0.0;
      for (std::size_t k = 0; k < 3; ++k) {
        dot += t[4 * k + i] * t[4 * k + j];
      }
      if (std::abs(dot - (i == j ? 1.0 : 0.0)) > kTol) {
        return "rotation block is not orthonormal";
      }
    }
  }
  const double det = t[0] * (t[5] * t[10] - t[6] * t[9]) - t[1] * (t[4] * t[10] - t[6] * t[8]) +
                     t[2] * (t[4] * t[9] - t[5] * t[8]);
  if (det < 0.0) {
    return "rotation block has determinant -1 (a reflection)";
  }
  if (std::hypot(t[3], t[7], t[11]) > kMaxCameraOffsetM) {
    return "translation more than 10 m from the body's origin";
  }
  return nullptr;
}

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
