#include "overlay.hpp"

#include <png.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <cstring>

namespace cleanslam::tools::track {

namespace fe = slam_core::frontend;

Overlay::Overlay(const hal::GrayImageView& image)
    : width_(image.width),
      height_(image.height),
      rgb_(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3U) {
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const std::uint8_t g = image.at(x, y);
      pixel(x, y, {g, g, g});
    }
  }
}

void Overlay::pixel(int x, int y, Rgb c) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) {
    return;
  }
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                         static_cast<std::size_t>(x)) *
                        3U;
  rgb_[i] = c.r;
  rgb_[i + 1] = c.g;
  rgb_[i + 2] = c.b;
}

void Overlay::line(double x0, double y0, double x1, double y1, Rgb c) {
  const double len = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
  const int n = static_cast<int>(std::ceil(len)) + 1;
  for (int i = 0; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    pixel(static_cast<int>(std::lround(x0 + t * (x1 - x0))),
          static_cast<int>(std::lround(y0 + t * (y1 - y0))), c);
  }
}

void Overlay::box(double x, double y, int half, Rgb c) {
  const double h = half;
  line(x - h, y - h, x + h, y - h, c);
  line(x + h, y - h, x + h, y + h, c);
  line(x + h, y + h, x - h, y + h, c);
  line(x - h, y + h, x - h, y - h, c);
}

void Overlay::cross(double x, double y, int half, Rgb c) {
  const double h = half;
  line(x - h, y - h, x + h, y + h, c);
  line(x - h, y + h, x + h, y - h, c);
}

void Overlay::ellipse(const fe::SearchRegion& region, Rgb c) {
  const Eigen::Matrix2d S = region.S_inv.inverse();
  const Eigen::LLT<Eigen::Matrix2d> llt(S);
  if (llt.info() != Eigen::Success) {
    return;
  }
  const Eigen::Matrix2d L = llt.matrixL();
  const double r = std::sqrt(region.gate_chi2);
  constexpr int kSegments = 48;
  Eigen::Vector2d prev = region.center + r * L * Eigen::Vector2d(1.0, 0.0);
  for (int i = 1; i <= kSegments; ++i) {
    const double a = 2.0 * M_PI * i / kSegments;
    const Eigen::Vector2d p = region.center + r * L * Eigen::Vector2d(std::cos(a), std::sin(a));
    line(prev.x(), prev.y(), p.x(), p.y(), c);
    prev = p;
  }
}

void Overlay::draw(const fe::FramePipeline& pipeline) {
  constexpr Rgb kYellow{230, 200, 0};
  constexpr Rgb kGreen{0, 220, 0};
  constexpr Rgb kRed{240, 0, 0};
  constexpr Rgb kMagenta{220, 0, 220};
  constexpr Rgb kCyan{0, 200, 230};
  for (int i = 0; i < pipeline.track_count(); ++i) {
    const fe::TrackRecord& t = pipeline.tracks()[i];
    ellipse(t.region, kYellow);
    if (t.result.found) {
      line(t.region.center.x(), t.region.center.y(), t.result.u_px, t.result.v_px, kMagenta);
      box(t.result.u_px, t.result.v_px, fe::kPatchRadius, t.inlier ? kGreen : kRed);
    } else {
      cross(t.region.center.x(), t.region.center.y(), 3, kRed);
    }
  }
  for (int i = 0; i < pipeline.new_landmark_count(); ++i) {
    const fe::PixelObservation& o = pipeline.new_landmark(i);
    box(o.u_px, o.v_px, fe::kPatchRadius, kCyan);
  }
}

bool Overlay::write_png(const std::string& path, std::string& error) const {
  png_image img;
  std::memset(&img, 0, sizeof(img));
  img.version = PNG_IMAGE_VERSION;
  img.width = static_cast<png_uint_32>(width_);
  img.height = static_cast<png_uint_32>(height_);
  img.format = PNG_FORMAT_RGB;
  if (png_image_write_to_file(&img, path.c_str(), 0, rgb_.data(), 0, nullptr) == 0) {
    error = path + ": " + img.message;
    return false;
  }
  return true;
}

}  // namespace cleanslam::tools::track
