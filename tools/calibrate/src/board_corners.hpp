#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "cleanslam/calibrate/camera_calibration.hpp"

// Finding a checkerboard's inner corners in an image, for the camera's and the mount's
// calibration (inside the calibrate library: OpenCV types do not leave it).
namespace cleanslam::calibrate {

// The board's inner corners in an 8-bit gray image, rows of `cols`, sub-pixel:
// findChessboardCorners with image normalization, then without (it misses boards seen at a
// grazing angle with it), each refined by cornerSubPix, then findChessboardCornersSB; false when
// none finds the board.
bool find_board_corners(const cv::Mat& gray, const Checkerboard& board,
                        std::vector<cv::Point2f>& corners);

}  // namespace cleanslam::calibrate
