#pragma once

#include <cstdint>

namespace cleanslam::drivers {

enum class PixelLayout : std::uint8_t { kGrey, kYuyv };

// Luma of a GREY or YUYV image of `width` x `height` (row stride in bytes), reduced by the
// integer factor `scale` with a scale x scale box average, into `out` (width/scale x
// height/scale, tightly packed).
void extract_luma(const std::uint8_t* image, int width, int height, int stride, PixelLayout layout,
                  int scale, std::uint8_t* out);

}  // namespace cleanslam::drivers
