#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cleanslam/hal/image.hpp"
#include "cleanslam/readers/result.hpp"

namespace cleanslam::readers {

// An owned 8-bit grayscale image, rows packed.
struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;

  GrayImage() = default;
  GrayImage(int w, int h, std::uint8_t fill = 0)
      : width(w),
        height(h),
        pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}
  [[nodiscard]] hal::GrayImageView view() const {
    return hal::GrayImageView{pixels.data(), width, height, width};
  }
  std::uint8_t& at(int x, int y) {
    return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                  static_cast<std::size_t>(x)];
  }
  [[nodiscard]] std::uint8_t at(int x, int y) const {
    return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                  static_cast<std::size_t>(x)];
  }
};

struct ImageSize {
  int width = 0;
  int height = 0;
};

// Reads a binary PGM (P5, maxval <= 255) or an 8-bit grayscale PNG, chosen by the file's magic
// bytes. `out` keeps its buffer capacity across calls. Errors name the path.
Status read_gray_image(const std::string& path, GrayImage& out);
// Reads only the header to learn the size (and that the file is a supported gray image).
Result<ImageSize> read_gray_image_size(const std::string& path);

}  // namespace cleanslam::readers
