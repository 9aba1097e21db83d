#pragma once

// Synthetic images for the front-end tests and benchmarks: a procedural texture (two layers of
// randomly shaded square cells at different sizes and angles, so that cell corners give Harris
// corners everywhere) rendered through a known similarity warp, with optional illumination gain
// and offset. Ground truth is exact: a texture point t appears at warp(t).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "cleanslam/hal/image.hpp"

namespace cleanslam::test {

struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;

  GrayImage() = default;
  GrayImage(int w, int h, std::uint8_t fill = 0)
      : width(w),
        height(h),
        pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}
  [[nodiscard]] hal::GrayImageView view() const { return {pixels.data(), width, height, width}; }
  std::uint8_t& at(int x, int y) {
    return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                  static_cast<std::size_t>(x)];
  }
};

// Image point = center + scale * R(angle) * (texture point - center) + shift.
struct Warp {
  double scale = 1.0;
  double angle_rad = 0.0;
  double shift_x = 0.0;
  double shift_y = 0.0;
  double center_x = 159.5;
  double center_y = 119.5;

  void apply(double tx, double ty, double& u, double& v) const {
    const double c = std::cos(angle_rad);
    const double s = std::sin(angle_rad);
    const double dx = tx - center_x;
    const double dy = ty - center_y;
    u = center_x + scale * (c * dx - s * dy) + shift_x;
    v = center_y + scale * (s * dx + c * dy) + shift_y;
  }
  void invert(double u, double v, double& tx, double& ty) const {
    const double c = std::cos(angle_rad);
    const double s = std::sin(angle_rad);
    const double du = (u - shift_x - center_x) / scale;
    const double dv = (v - shift_y - center_y) / scale;
    tx = center_x + c * du + s * dv;
    ty = center_y - s * du + c * dv;
  }
};

inline double hash01(std::int64_t i, std::int64_t j, std::uint32_t seed) {
  auto h = static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ULL ^
           (static_cast<std::uint64_t>(j) + 0x632BE59BD9B4E019ULL +
            (static_cast<std::uint64_t>(seed) << 32));
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

struct TextureOptions {
  std::uint32_t seed = 1;
  // Columns [periodic_x0, periodic_x1) of the texture repeat with this period (0: none).
  double period_x = 0.0;
  double periodic_x0 = 0.0;
  double periodic_x1 = 0.0;
};

// Gray level in [20, 235] of the texture at (x, y).
inline double texture(double x, double y, const TextureOptions& opt = {}) {
  if (opt.period_x > 0.0 && x >= opt.periodic_x0 && x < opt.periodic_x1) {
    x = opt.periodic_x0 + std::fmod(x - opt.periodic_x0, opt.period_x);
  }
  const double a1 = 0.35;
  const double c1 = std::cos(a1);
  const double s1 = std::sin(a1);
  const double x1 = (c1 * x + s1 * y) / 14.0;
  const double y1 = (-s1 * x + c1 * y) / 14.0;
  const double a2 = -0.6;
  const double c2 = std::cos(a2);
  const double s2 = std::sin(a2);
  const double x2 = (c2 * x + s2 * y) / 23.0;
  const double y2 = (-s2 * x + c2 * y) / 23.0;
  const double g1 = hash01(static_cast<std::int64_t>(std::floor(x1)),
                           static_cast<std::int64_t>(std::floor(y1)), opt.seed);
  const double g2 = hash01(static_cast<std::int64_t>(std::floor(x2)),
                           static_cast<std::int64_t>(std::floor(y2)), opt.seed + 7U);
  return 20.0 + 215.0 * (0.6 * g1 + 0.4 * g2);
}

// Renders the texture through `warp` with `supersample`^2 samples per pixel, then applies
// gain * value + offset (saturating).
inline GrayImage render(const Warp& warp, int width = 320, int height = 240, double gain = 1.0,
                        double offset = 0.0, const TextureOptions& opt = {}, int supersample = 3) {
  GrayImage img(width, height);
  const double step = 1.0 / supersample;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double sum = 0.0;
      for (int sy = 0; sy < supersample; ++sy) {
        for (int sx = 0; sx < supersample; ++sx) {
          const double u = x - 0.5 + (sx + 0.5) * step;
          const double v = y - 0.5 + (sy + 0.5) * step;
          double tx = 0.0;
          double ty = 0.0;
          warp.invert(u, v, tx, ty);
          sum += texture(tx, ty, opt);
        }
      }
      const double value = gain * sum / (supersample * supersample) + offset;
      img.at(x, y) = static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L));
    }
  }
  return img;
}

}  // namespace cleanslam::test
