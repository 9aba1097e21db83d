#pragma once

#include <array>
#include <string>
#include <vector>

#include "cleanslam/calibrate/camera_calibration.hpp"
#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/readers/result.hpp"

// The camera's mount T_body_cam from a checkerboard lying flat on the floor at a measured spot in
// front of the robot: the board's corners are known in the body frame, so the camera's pose in
// the body frame is the perspective-n-point solution (OpenCV solvePnP) through the calibrated
// intrinsics.
namespace cleanslam::calibrate {

// Where the board lies: its centre (the middle of its inner corners) in the body frame (x
// forward, y left, on the floor) and the direction of its rows of `cols` corners from the body's
// x axis, counter-clockwise. The corners are symmetric under a half turn, so yaw and yaw + 180
// degrees are the same board.
struct BoardOnFloor {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
};

struct MountCalibration {
  std::array<double, 16> T_body_cam{};  // row-major, the camera's optical frame in the body frame
  double rms_px = 0.0;
  int views = 0;
  double height_m = 0.0;  // the camera's centre above the floor
  double tilt_deg = 0.0;  // optical axis above the horizontal
  double yaw_deg = 0.0;   // optical axis from the body's x axis, counter-clockwise
};

// The board's corners in the body frame, in findChessboardCorners' order.
std::vector<std::array<double, 3>> board_corners_on_floor(const Checkerboard& board,
                                                          const BoardOnFloor& spot);

// Refused, naming the image, when the board is not found in one; or when the reprojection error
// exceeds `max_rms_px` (wrong intrinsics, a board that is not flat). A wrong spot, yaw or square
// size cannot be seen: it moves the camera (the report's height and tilt are to be checked).
readers::Result<MountCalibration> calibrate_mount(const Views& views, const Checkerboard& board,
                                                  const BoardOnFloor& spot,
                                                  const hal::CameraCalibration& camera,
                                                  double max_rms_px = 2.0);
inline readers::Result<MountCalibration> calibrate_mount(const std::vector<std::string>& images,
                                                         const Checkerboard& board,
                                                         const BoardOnFloor& spot,
                                                         const hal::CameraCalibration& camera,
                                                         double max_rms_px = 2.0) {
  return calibrate_mount(Views{images, {}}, board, spot, camera, max_rms_px);
}

}  // namespace cleanslam::calibrate
