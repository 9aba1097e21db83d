#pragma once

#include <cstdint>

namespace cleanslam::hal {

// Non-owning view of an 8-bit grayscale image; row r starts at data + r * stride.
struct GrayImageView {
  const std::uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  int stride = 0;

  [[nodiscard]] bool empty() const { return data == nullptr || width <= 0 || height <= 0; }
  [[nodiscard]] std::uint8_t at(int x, int y) const {
    return data[static_cast<long>(y) * stride + x];
  }
  [[nodiscard]] const std::uint8_t* row(int y) const {
    return data + static_cast<long>(y) * stride;
  }
};

}  // namespace cleanslam::hal
