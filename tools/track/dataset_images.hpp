#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cleanslam/hal/image.hpp"
#include "cleanslam/hal/time.hpp"

namespace cleanslam::tools::track {

struct FrameEntry {
  hal::TimeNs t_ns = 0;
  std::string path;  // absolute or relative to the working directory
};

struct DatasetImages {
  int width = 0;
  int height = 0;
  std::vector<FrameEntry> frames;
};

struct OwnedImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
  [[nodiscard]] hal::GrayImageView view() const { return {pixels.data(), width, height, width}; }
};

// Reads camera.width/height from DATASET/sensors.yaml and the frame list of
// DATASET/cam0/data.csv (docs/dataset-format.md). On failure returns false with a message naming
// the file, line and value at fault.
bool load_dataset_images(const std::string& dataset, DatasetImages& out, std::string& error);

// 8-bit grayscale PNG (other PNG formats are converted to gray) or binary PGM (P5, maxval 255).
bool load_gray_image(const std::string& path, OwnedImage& out, std::string& error);

}  // namespace cleanslam::tools::track
