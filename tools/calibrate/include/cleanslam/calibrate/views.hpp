#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

// The images a camera or mount calibration looks at: image files, decoded one at a time when
// needed, or grey images already in memory (a firmware log's frames).
namespace cleanslam::calibrate {

// An 8-bit grey image, rows packed (no padding), named for messages.
struct GrayImage {
  std::string name;
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // width * height
};

struct Views {
  std::vector<std::string> files;  // image files (png, jpg, pgm, bmp), or
  std::vector<GrayImage> images;   // images in memory

  [[nodiscard]] std::size_t size() const { return files.empty() ? images.size() : files.size(); }
  [[nodiscard]] bool empty() const { return size() == 0; }
  // The file's path or the image's name.
  [[nodiscard]] const std::string& name(std::size_t i) const {
    return files.empty() ? images[i].name : files[i];
  }
};

}  // namespace cleanslam::calibrate
