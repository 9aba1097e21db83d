#pragma once

#include <string>

#include "cleanslam/hal/image.hpp"
#include "cleanslam/readers/result.hpp"

// The dataset's image files (cam0/data/), read back by readers::read_gray_image.
namespace cleanslam::sim_hal {

readers::Status write_pgm(const std::string& path, const hal::GrayImageView& image);
readers::Status write_png(const std::string& path, const hal::GrayImageView& image);

}  // namespace cleanslam::sim_hal
