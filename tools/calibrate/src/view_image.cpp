#include "view_image.hpp"

#include <opencv2/imgcodecs.hpp>

namespace cleanslam::calibrate {

cv::Mat view_image(const Views& views, std::size_t i) {
  if (!views.files.empty()) {
    return cv::imread(views.files[i], cv::IMREAD_GRAYSCALE);
  }
  const GrayImage& g = views.images[i];
  if (g.width <= 0 || g.height <= 0 ||
      g.pixels.size() != static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height)) {
    return {};
  }
  // cv::Mat does not write through this pointer: the calibration only reads its images.
  return {g.height, g.width, CV_8UC1, const_cast<std::uint8_t*>(g.pixels.data())};  // NOLINT
}

}  // namespace cleanslam::calibrate
