#include "cleanslam/drivers/luma.hpp"

namespace cleanslam::drivers {

void extract_luma(const std::uint8_t* image, int width, int height, int stride, PixelLayout layout,
                  int scale, std::uint8_t* out) {
  const int step = layout == PixelLayout::kYuyv ? 2 : 1;
  const int out_width = width / scale;
  const int out_height = height / scale;
  if (scale == 1) {
    for (int y = 0; y < out_height; ++y) {
      const std::uint8_t* row = image + static_cast<long>(y) * stride;
      std::uint8_t* dst = out + static_cast<long>(y) * out_width;
      for (int x = 0; x < out_width; ++x) {
        dst[x] = row[x * step];
      }
    }
    return;
  }
  const unsigned area = static_cast<unsigned>(scale * scale);
  for (int y = 0; y < out_height; ++y) {
    std::uint8_t* dst = out + static_cast<long>(y) * out_width;
    for (int x = 0; x < out_width; ++x) {
      unsigned sum = 0;
      for (int dy = 0; dy < scale; ++dy) {
        const std::uint8_t* row = image + static_cast<long>(y * scale + dy) * stride;
        for (int dx = 0; dx < scale; ++dx) {
          sum += row[(x * scale + dx) * step];
        }
      }
      dst[x] = static_cast<std::uint8_t>((sum + area / 2) / area);
    }
  }
}

}  // namespace cleanslam::drivers
