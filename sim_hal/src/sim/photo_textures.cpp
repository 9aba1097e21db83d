#include "cleanslam/sim_hal/sim/photo_textures.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace cleanslam::sim_hal::sim {
namespace {

double texel(const std::vector<float>& t, int w, int h, int x, int y) {
  x = ((x % w) + w) % w;
  y = ((y % h) + h) % h;
  return static_cast<double>(
      t[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)]);
}

// Any PNG (gray, colour, palette, 16 bits) as 8-bit gray; an empty string or the reason it failed.
std::string read_png_as_gray(const std::string& path, int& width, int& height,
                             std::vector<std::uint8_t>& pixels) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&png, path.c_str()) == 0) {
    std::string why = png.message;
    png_image_free(&png);
    return path + ": " + why;
  }
  png.format = PNG_FORMAT_GRAY;
  width = static_cast<int>(png.width);
  height = static_cast<int>(png.height);
  pixels.resize(PNG_IMAGE_SIZE(png));
  if (png_image_finish_read(&png, nullptr, pixels.data(), 0, nullptr) == 0) {
    std::string why = png.message;
    png_image_free(&png);
    return path + ": " + why;
  }
  return {};
}

}  // namespace

const std::vector<std::string>& PhotoTextures::file_names() {
  // 0-2 surfaces (bricks, gravel, grass), 3.. framed pictures and furniture fronts.
  static const std::vector<std::string> names = {"brick.png",     "gravel.png", "grass.png",
                                                 "camera.png",    "coffee.png", "chelsea.png",
                                                 "astronaut.png", "coins.png",  "text.png"};
  return names;
}

void PhotoTextures::load(const std::string& dir, std::vector<std::string>& missing) {
  photos_.clear();
  missing_ = 0;
  std::vector<std::uint8_t> pixels;
  for (const std::string& name : file_names()) {
    int width = 0;
    int height = 0;
    std::string path = dir;
    path += '/';
    path += name;
    std::string error = read_png_as_gray(path, width, height, pixels);
    if (error.empty() && (width < 2 || height < 2)) {
      error = path;
      error += ": too small";
    }
    if (!error.empty()) {
      missing.push_back(error);
      ++missing_;
      continue;
    }
    std::vector<Level> pyramid(1);
    Level& base = pyramid[0];
    base.width = width;
    base.height = height;
    base.texels.resize(pixels.size());
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      base.texels[i] = static_cast<float>(pixels[i]) / 255.0F;
    }
    while (pyramid.back().width >= 4 && pyramid.back().height >= 4) {
      const Level& f = pyramid.back();
      Level c;
      c.width = f.width / 2;
      c.height = f.height / 2;
      c.texels.resize(static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height));
      for (int y = 0; y < c.height; ++y) {
        for (int x = 0; x < c.width; ++x) {
          const double sum = texel(f.texels, f.width, f.height, 2 * x, 2 * y) +
                             texel(f.texels, f.width, f.height, 2 * x + 1, 2 * y) +
                             texel(f.texels, f.width, f.height, 2 * x, 2 * y + 1) +
                             texel(f.texels, f.width, f.height, 2 * x + 1, 2 * y + 1);
          c.texels[static_cast<std::size_t>(y) * static_cast<std::size_t>(c.width) +
                   static_cast<std::size_t>(x)] = static_cast<float>(0.25 * sum);
        }
      }
      pyramid.push_back(std::move(c));
    }
    photos_.push_back(std::move(pyramid));
  }
}

double PhotoTextures::aspect(std::size_t index) const {
  const Level& l = photos_[index % photos_.size()][0];
  return static_cast<double>(l.height) / static_cast<double>(l.width);
}

double PhotoTextures::sample(std::size_t index, double s, double t, double footprint) const {
  const auto& pyramid = photos_[index % photos_.size()];
  const double texels_covered = footprint * static_cast<double>(pyramid[0].width);
  const int top = static_cast<int>(pyramid.size()) - 1;
  const int level = texels_covered > 1.0
                        ? std::min(top, static_cast<int>(std::lround(std::log2(texels_covered))))
                        : 0;
  const Level& l = pyramid[static_cast<std::size_t>(level)];
  const double x = (s - std::floor(s)) * l.width - 0.5, y = (t - std::floor(t)) * l.height - 0.5;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  const double top_row = (1.0 - fx) * texel(l.texels, l.width, l.height, x0, y0) +
                         fx * texel(l.texels, l.width, l.height, x0 + 1, y0);
  const double bottom_row = (1.0 - fx) * texel(l.texels, l.width, l.height, x0, y0 + 1) +
                            fx * texel(l.texels, l.width, l.height, x0 + 1, y0 + 1);
  return (1.0 - fy) * top_row + fy * bottom_row;
}

}  // namespace cleanslam::sim_hal::sim
