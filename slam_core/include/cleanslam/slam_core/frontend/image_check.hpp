#pragma once

#include <cstddef>
#include <cstdint>

#include "cleanslam/hal/image.hpp"

namespace cleanslam::slam_core::frontend {

// Why an image cannot be used by the front end; kOk when it can.
enum class ImageCheck : std::uint8_t {
  kOk,
  kEmpty,
  kWrongSize,
  kBadStride,
  kTooLarge,
};

// The front end works on images of exactly the configured size (at most hal::kImageWidth x
// hal::kImageHeight), with stride >= width.
[[nodiscard]] ImageCheck check_image(const hal::GrayImageView& image, int expected_width,
                                     int expected_height);

// A message naming the values at fault, e.g. "image 640x480 does not match the configured
// 320x240", written into `out` (always NUL-terminated). Returns `out`.
const char* describe_image_check(ImageCheck check, const hal::GrayImageView& image,
                                 int expected_width, int expected_height, char* out,
                                 std::size_t out_size);

}  // namespace cleanslam::slam_core::frontend
