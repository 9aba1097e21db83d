#pragma once

#include <opencv2/core.hpp>

#include "cleanslam/calibrate/views.hpp"

// One view as OpenCV sees it (inside the calibrate library: OpenCV types do not leave it).
namespace cleanslam::calibrate {

// The i-th view as an 8-bit grey cv::Mat: the file decoded (cv::imread, grey), or the image in
// memory wrapped without a copy (valid while `views` is). Empty when the file cannot be read.
cv::Mat view_image(const Views& views, std::size_t i);

}  // namespace cleanslam::calibrate
