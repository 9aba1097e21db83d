#pragma once

#include <cmath>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/capacities.hpp"

// The values of each calibration number that cleanslam accepts. The dataset's sensors.yaml and the
// firmware configuration's `calibration` section are both checked against these, so that a
// recording and a robot refuse the same nonsense (a negative noise, a lever arm of 1e7 m).
namespace cleanslam::hal::calibration_limits {

struct Limit {
  double lo;
  double hi;
  bool lo_open;  // lo itself is outside
  [[nodiscard]] constexpr bool contains(double v) const {
    return (lo_open ? v > lo : v >= lo) && v <= hi;
  }
};

// "v is out of range (lo, hi]", as the firmware configuration words it for every key.
inline std::string out_of_range(double v, Limit limit) {
  std::ostringstream s;
  s << v << " is out of range " << (limit.lo_open ? "(" : "[") << limit.lo << ", " << limit.hi
    << "]";
  return s.str();
}

// The camera's geometry is checked as a whole (camera_geometry_error below): the image no larger
// than the front end takes, the principal point inside the image, and a field of view across
// each side from kMinFieldOfViewDeg to kMaxFieldOfViewDeg. Outside these the estimator is blind:
// points never fall in the image, or every ray is the same one.
inline constexpr Limit kImageWidthPx{1.0, static_cast<double>(kImageWidth), false};
inline constexpr Limit kImageHeightPx{1.0, static_cast<double>(kImageHeight), false};
inline constexpr double kMinFieldOfViewDeg = 10.0;
inline constexpr double kMaxFieldOfViewDeg = 150.0;
// The focal lengths (pixels) whose field of view across `side_px` pixels is within the bounds.
inline Limit focal_limit(int side_px) {
  const double half_rad = 0.5 * 3.14159265358979323846 / 180.0;
  const double side = static_cast<double>(side_px);
  return {0.5 * side / std::tan(kMaxFieldOfViewDeg * half_rad),
          0.5 * side / std::tan(kMinFieldOfViewDeg * half_rad), false};
}
// The principal point inside the image of `side_px` pixels (pixel centres at 0 ... side - 1).
inline Limit principal_point_limit(int side_px) {
  return {-0.5, static_cast<double>(side_px) - 0.5, false};
}
inline constexpr Limit kDistortion{-100.0, 100.0, false};  // each of k1 k2 p1 p2
inline constexpr Limit kPixelNoisePx{0.0, 100.0, true};
inline constexpr Limit kTimeOffsetS{-1.0, 1.0, false};
// A camera time offset beyond this is accepted with a warning: more than a frame period at 2 Hz.
inline constexpr double kPlausibleTimeOffsetS = 0.5;
inline std::string implausible_time_offset(double v) {
  std::ostringstream s;
  s << v << " s is more than " << kPlausibleTimeOffsetS
    << " s: frames are matched to the odometry that far away (is it in seconds?)";
  return s.str();
}
// At least a tick per centimetre of travel: fewer, and the 20 Hz samples would not see the robot
// move.
inline constexpr Limit kTicksPerMeter{100.0, 1e7, false};
inline constexpr Limit kWheelBaseM{0.0, 10.0, true};
inline constexpr Limit kFraction{0.0, 1.0, false};  // distance_noise and both scale_error
inline constexpr Limit kNoiseDensity{0.0, 1.0, true};
inline constexpr Limit kGyroBias{0.0, 1.0, false};  // bias_instability and bias_walk

// One error of a camera's size or intrinsics: the key (of the `camera` mapping) and what is
// wrong with its value.
struct CameraKeyError {
  const char* key;
  std::string message;  // "1e-06 is out of range [42.87, 1829]: the field of view across ..."
};

// What is wrong with a camera's size and intrinsics, each naming the value and the allowed range;
// empty when nothing is. `prefix` is the dotted path of the camera mapping ("camera." in
// sensors.yaml), used where a message names another key.
inline std::vector<CameraKeyError> camera_geometry_errors(const CameraCalibration& c,
                                                          const std::string& prefix) {
  std::vector<CameraKeyError> errors;
  // The value as written (to 10 digits), the limits to 4.
  const auto range = [](double v, Limit limit) {
    std::ostringstream s;
    s.precision(10);
    s << v << " is out of range [";
    s.precision(4);
    s << limit.lo << ", " << limit.hi << "]: ";
    return s.str();
  };
  for (const auto& [key, v, limit] : {std::tuple{"width", c.width, kImageWidthPx},
                                      std::tuple{"height", c.height, kImageHeightPx}}) {
    if (!limit.contains(v)) {
      errors.push_back({key, range(v, limit) + "the front end takes images of at most " +
                                 std::to_string(kImageWidth) + "x" + std::to_string(kImageHeight) +
                                 " pixels"});
    }
  }
  if (!errors.empty()) {
    return errors;
  }
  std::ostringstream fov;
  fov << kMinFieldOfViewDeg << " to " << kMaxFieldOfViewDeg << " degrees";
  for (const auto& [key, f, side_key, side] :
       {std::tuple{"fx", c.fx, "width", c.width}, std::tuple{"fy", c.fy, "height", c.height}}) {
    const Limit limit = focal_limit(side);
    if (!limit.contains(f)) {
      errors.push_back({key, range(f, limit) + "the field of view across " + prefix + side_key +
                                 " " + std::to_string(side) + " px must be " + fov.str()});
    }
  }
  for (const auto& [key, v, side_key, side] :
       {std::tuple{"cx", c.cx, "width", c.width}, std::tuple{"cy", c.cy, "height", c.height}}) {
    const Limit limit = principal_point_limit(side);
    if (!limit.contains(v)) {
      errors.push_back({key, range(v, limit) + "the principal point must be inside the image (" +
                                 prefix + side_key + " " + std::to_string(side) + " px)"});
    }
  }
  return errors;
}

}  // namespace cleanslam::hal::calibration_limits
