#include "board_corners.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace cleanslam::calibrate {

bool find_board_corners(const cv::Mat& gray, const Checkerboard& board,
                        std::vector<cv::Point2f>& corners) {
  const cv::Size pattern(board.cols, board.rows);
  for (const int flags : {cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE,
                          int{cv::CALIB_CB_ADAPTIVE_THRESH}}) {
    if (cv::findChessboardCorners(gray, pattern, corners, flags)) {
      cv::cornerSubPix(gray, corners, cv::Size(5, 5), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.01));
      return true;
    }
  }
  return cv::findChessboardCornersSB(gray, pattern, corners);
}

}  // namespace cleanslam::calibrate
