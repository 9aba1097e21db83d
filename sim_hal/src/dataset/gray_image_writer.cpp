#include "cleanslam/sim_hal/gray_image_writer.hpp"

#include <png.h>

#include <fstream>

namespace cleanslam::sim_hal {

readers::Status write_pgm(const std::string& path, const hal::GrayImageView& image) {
  if (image.empty()) {
    return readers::Status::failure(path + ": empty image");
  }
  std::ofstream out(path, std::ios::binary);
  if (!out) {
    return readers::Status::failure(path + ": cannot create file");
  }
  out << "P5\n" << image.width << ' ' << image.height << "\n255\n";
  for (int y = 0; y < image.height; ++y) {
    out.write(reinterpret_cast<const char*>(image.row(y)), image.width);
  }
  out.close();
  if (!out) {
    return readers::Status::failure(path + ": write error");
  }
  return readers::Status();
}

readers::Status write_png(const std::string& path, const hal::GrayImageView& image) {
  if (image.empty()) {
    return readers::Status::failure(path + ": empty image");
  }
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_GRAY;
  const int ok = png_image_write_to_file(&png, path.c_str(), 0, image.data, image.stride, nullptr);
  const std::string message = png.message;
  png_image_free(&png);
  if (ok == 0) {
    return readers::Status::failure(path + ": PNG write error: " + message);
  }
  return readers::Status();
}

}  // namespace cleanslam::sim_hal
