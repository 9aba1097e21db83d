#include "overlay.hpp"

#include <png.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "overlay_font.hpp"

namespace cleanslam::tools::track {

namespace fe = slam_core::frontend;

namespace {

constexpr int kSmallImageWidth = 400;  // enlarged twice up to this width
constexpr int kLineHeight = kGlyphHeight + 4;
constexpr int kLegendColumnWidth = 210;
constexpr int kStripPadding = 4;
constexpr Overlay::Rgb kYellow{230, 200, 0};
constexpr Overlay::Rgb kGreen{0, 220, 0};
constexpr Overlay::Rgb kRed{240, 0, 0};
constexpr Overlay::Rgb kMagenta{220, 0, 220};
constexpr Overlay::Rgb kCyan{0, 200, 230};
constexpr Overlay::Rgb kWhite{235, 235, 235};
constexpr Overlay::Rgb kStrip{24, 24, 24};

}  // namespace

Overlay::Overlay(const hal::GrayImageView& image)
    : scale_(image.width <= kSmallImageWidth ? 2 : 1),
      image_height_(image.height * scale_),
      width_(image.width * scale_),
      height_(0) {
  const int columns = std::max(1, width_ / kLegendColumnWidth);
  const int legend_rows = (6 + columns - 1) / columns;
  height_ = image_height_ + 2 * kStripPadding + (1 + legend_rows) * kLineHeight;
  rgb_.resize(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * 3U);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const std::uint8_t g = y < image_height_ ? image.at(x / scale_, y / scale_) : 0U;
      pixel(x, y, y < image_height_ ? Rgb{g, g, g} : kStrip);
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

Overlay::Rgb Overlay::at(int x, int y) const {
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                         static_cast<std::size_t>(x)) *
                        3U;
  return {rgb_[i], rgb_[i + 1], rgb_[i + 2]};
}

double Overlay::canvas(double image_px) const {
  return (image_px + 0.5) * scale_ - 0.5;
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

void Overlay::box(double x, double y, double half, Rgb c) {
  line(x - half, y - half, x + half, y - half, c);
  line(x + half, y - half, x + half, y + half, c);
  line(x + half, y + half, x - half, y + half, c);
  line(x - half, y + half, x - half, y - half, c);
}

void Overlay::cross(double x, double y, double half, Rgb c) {
  line(x - half, y - half, x + half, y + half, c);
  line(x - half, y + half, x + half, y - half, c);
}

void Overlay::mark(Mark m, double x, double y) {
  const double patch = fe::kPatchRadius * scale_;
  switch (m) {
    case Mark::kRegion:
      for (int i = 0; i < 24; ++i) {
        const double a0 = 2.0 * M_PI * i / 24;
        const double a1 = 2.0 * M_PI * (i + 1) / 24;
        line(x + 8.0 * std::cos(a0), y + 4.0 * std::sin(a0), x + 8.0 * std::cos(a1),
             y + 4.0 * std::sin(a1), kYellow);
      }
      break;
    case Mark::kShift:
      line(x - 8.0, y + 3.0, x + 8.0, y - 3.0, kMagenta);
      break;
    case Mark::kInlier:
      box(x, y, std::min(patch, 5.0), kGreen);
      break;
    case Mark::kOutlier:
      box(x, y, std::min(patch, 5.0), kRed);
      break;
    case Mark::kNotFound:
      cross(x, y, 3.0 * scale_ / 2.0, kRed);
      break;
    case Mark::kNew:
      box(x, y, std::min(patch, 5.0), kCyan);
      break;
  }
}

void Overlay::text(int x, int y, const std::string& s, Rgb c) {
  for (const char ch : s) {
    const std::uint8_t* rows = glyph_rows(ch);
    for (int r = 0; r < kGlyphHeight; ++r) {
      for (int col = 0; col < kGlyphWidth; ++col) {
        if ((rows[r] & (0x80U >> static_cast<unsigned>(col))) != 0U) {
          pixel(x + col, y + r, c);
        }
      }
    }
    x += kGlyphWidth;
  }
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
    line(canvas(prev.x()), canvas(prev.y()), canvas(p.x()), canvas(p.y()), c);
    prev = p;
  }
}

void Overlay::strip(const fe::FrameReport& report, const FrameCaption& caption) {
  char line_text[160];
  std::snprintf(line_text, sizeof(line_text),
                "frame %ld  t %.3f s  searched %d  inliers %d  outliers %d  new %d", caption.frame,
                caption.t_s, report.searched, report.inliers, report.outliers, report.initialized);
  const int top = image_height_ + kStripPadding;
  text(kStripPadding, top + 2, line_text, kWhite);
  static constexpr std::array<std::pair<Mark, const char*>, 6> kLegend{{
      {Mark::kRegion, "search region (gate)"},
      {Mark::kShift, "prediction to match"},
      {Mark::kInlier, "inlier"},
      {Mark::kOutlier, "outlier"},
      {Mark::kNotFound, "not found"},
      {Mark::kNew, "new landmark"},
  }};
  const int columns = std::max(1, width_ / kLegendColumnWidth);
  for (std::size_t i = 0; i < kLegend.size(); ++i) {
    const int col = static_cast<int>(i) % columns;
    const int row = 1 + static_cast<int>(i) / columns;
    const int x = kStripPadding + col * kLegendColumnWidth;
    const int y = top + row * kLineHeight;
    mark(kLegend[i].first, x + 10.0, y + 2.0 + kGlyphHeight / 2.0);
    text(x + 24, y + 2, kLegend[i].second, kWhite);
  }
}

void Overlay::draw(const fe::FramePipeline& pipeline, const FrameCaption& caption) {
  for (int i = 0; i < pipeline.track_count(); ++i) {
    const fe::TrackRecord& t = pipeline.tracks()[i];
    ellipse(t.region, kYellow);
    const double cx = canvas(t.region.center.x());
    const double cy = canvas(t.region.center.y());
    if (t.result.found) {
      const double u = canvas(t.result.u_px);
      const double v = canvas(t.result.v_px);
      line(cx, cy, u, v, kMagenta);
      box(u, v, fe::kPatchRadius * scale_, t.inlier ? kGreen : kRed);
    } else {
      mark(Mark::kNotFound, cx, cy);
    }
  }
  for (int i = 0; i < pipeline.new_landmark_count(); ++i) {
    const fe::PixelObservation& o = pipeline.new_landmark(i);
    box(canvas(o.u_px), canvas(o.v_px), fe::kPatchRadius * scale_, kCyan);
  }
  strip(pipeline.report(), caption);
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
