#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "cleanslam/calibrate/views.hpp"
#include "cleanslam/readers/result.hpp"

// The camera's intrinsics and distortion (pinhole, radial-tangential k1 k2 p1 p2, as sensors.yaml)
// from images of a planar checkerboard (Zhang 2000, through OpenCV: findChessboardCorners,
// cornerSubPix, calibrateCamera). A PC tool: OpenCV is linked here only, never by the robot's
// program.
namespace cleanslam::calibrate {

struct Checkerboard {
  int cols = 0;  // inner corners along a row
  int rows = 0;
  double square_m = 0.0;
};

struct CameraCalibrationOptions {
  int min_views = 8;          // images in which the board is found
  double min_coverage = 0.5;  // the corners' union bounding box / the image's area
  double max_rms_px = 1.0;    // RMS reprojection error above this is refused
  // Called after each image: done, total, file (or image name), board found.
  std::function<void(int, int, const std::string&, bool)> progress;
};

struct CameraCalibration {
  int width = 0;
  int height = 0;
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  std::array<double, 4> distortion{};  // k1 k2 p1 p2
  double rms_px = 0.0;
  int views = 0;                      // images used
  int images = 0;                     // images read
  std::vector<std::string> rejected;  // images (names) without the board
  double coverage = 0.0;
  std::array<double, 4> corner_box{};  // min x, min y, max x, max y of all corners, px
};

// The image files of `folder` (png, jpg, jpeg, pgm, bmp), sorted by name.
std::vector<std::string> image_files(const std::string& folder);

// Refused, saying which, when an image cannot be read or has another size than the first, when
// too few images show the board, when their corners cover too little of the image (naming the
// edges to reach), or when the reprojection error is too large.
readers::Result<CameraCalibration> calibrate_camera(const Views& views, const Checkerboard& board,
                                                    const CameraCalibrationOptions& options);
inline readers::Result<CameraCalibration> calibrate_camera(
    const std::vector<std::string>& images, const Checkerboard& board,
    const CameraCalibrationOptions& options) {
  return calibrate_camera(Views{images, {}}, board, options);
}

// The intrinsics at another image size (the same camera binned or scaled): focal lengths and
// principal point scaled, about the top-left pixel's centre convention; distortion unchanged.
CameraCalibration scaled_to(const CameraCalibration& c, int width, int height);

}  // namespace cleanslam::calibrate
