#include "cleanslam/slam_core/frontend/image_check.hpp"

#include <cstdio>

#include "cleanslam/hal/capacities.hpp"

namespace cleanslam::slam_core::frontend {

ImageCheck check_image(const hal::GrayImageView& image, int expected_width, int expected_height) {
  if (expected_width > hal::kImageWidth || expected_height > hal::kImageHeight) {
    return ImageCheck::kTooLarge;
  }
  if (image.empty()) {
    return ImageCheck::kEmpty;
  }
  if (image.width != expected_width || image.height != expected_height) {
    return ImageCheck::kWrongSize;
  }
  if (image.stride < image.width) {
    return ImageCheck::kBadStride;
  }
  return ImageCheck::kOk;
}

const char* describe_image_check(ImageCheck check, const hal::GrayImageView& image,
                                 int expected_width, int expected_height, char* out,
                                 std::size_t out_size) {
  if (out == nullptr || out_size == 0) {
    return out;
  }
  switch (check) {
    case ImageCheck::kOk:
      std::snprintf(out, out_size, "image %dx%d ok", image.width, image.height);
      break;
    case ImageCheck::kEmpty:
      std::snprintf(out, out_size, "image is empty (data %s, %dx%d)",
                    image.data == nullptr ? "null" : "set", image.width, image.height);
      break;
    case ImageCheck::kWrongSize:
      std::snprintf(out, out_size, "image %dx%d does not match the configured %dx%d", image.width,
                    image.height, expected_width, expected_height);
      break;
    case ImageCheck::kBadStride:
      std::snprintf(out, out_size, "image stride %d is smaller than its width %d", image.stride,
                    image.width);
      break;
    case ImageCheck::kTooLarge:
      std::snprintf(out, out_size,
                    "configured image size %dx%d exceeds the capacity %dx%d (hal/capacities.hpp)",
                    expected_width, expected_height, hal::kImageWidth, hal::kImageHeight);
      break;
  }
  return out;
}

}  // namespace cleanslam::slam_core::frontend
