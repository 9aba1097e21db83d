#include "cleanslam/slam_core/frontend/harris.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace cleanslam::slam_core::frontend {

namespace {
constexpr int kPlaneSize = hal::kImageWidth * hal::kImageHeight;
// Candidates sorted by response before the minimum-distance pass.
constexpr int kMaxSortedCandidates = 4 * hal::kMaxCorners;
}  // namespace

struct HarrisDetector::Planes {
  static constexpr int kRing = 7;  // rows of the vertical blur window (2 * max radius + 1)
  // Structure-tensor products blurred along their row, for the last kRing image rows.
  std::array<float, std::size_t{kRing} * hal::kImageWidth> hxx{};
  std::array<float, std::size_t{kRing} * hal::kImageWidth> hxy{};
  std::array<float, std::size_t{kRing} * hal::kImageWidth> hyy{};
  std::array<float, hal::kImageWidth> gxx{};
  std::array<float, hal::kImageWidth> gxy{};
  std::array<float, hal::kImageWidth> gyy{};
  std::array<float, kPlaneSize> response{};
  std::array<Corner, kPlaneSize / 4 + hal::kImageWidth> candidates{};
};

namespace {

// Sobel gradients of image row y and their products, blurred along the row with the symmetric
// kernel k[0..2R] into oxx, oxy, oyy (columns 1 + R .. w - 2 - R).
template <int R>
void blurred_products_row(const hal::GrayImageView& image, int y, const float* kern, float* gxx,
                          float* gxy, float* gyy, float* __restrict oxx, float* __restrict oxy,
                          float* __restrict oyy) {
  const int w = image.width;
  const std::uint8_t* a = image.row(y - 1);
  const std::uint8_t* b = image.row(y);
  const std::uint8_t* c = image.row(y + 1);
  for (int x = 1; x < w - 1; ++x) {
    const int gx = (a[x + 1] - a[x - 1]) + 2 * (b[x + 1] - b[x - 1]) + (c[x + 1] - c[x - 1]);
    const int gy = (c[x - 1] - a[x - 1]) + 2 * (c[x] - a[x]) + (c[x + 1] - a[x + 1]);
    const auto fx = static_cast<float>(gx);
    const auto fy = static_cast<float>(gy);
    gxx[x] = fx * fx;
    gxy[x] = fx * fy;
    gyy[x] = fy * fy;
  }
  float k[R + 1];
  for (int i = 0; i <= R; ++i) {
    k[i] = kern[R + i];
  }
  for (int x = 1 + R; x < w - 1 - R; ++x) {
    float sxx = k[0] * gxx[x];
    float sxy = k[0] * gxy[x];
    float syy = k[0] * gyy[x];
    for (int i = 1; i <= R; ++i) {
      sxx += k[i] * (gxx[x - i] + gxx[x + i]);
      sxy += k[i] * (gxy[x - i] + gxy[x + i]);
      syy += k[i] * (gyy[x - i] + gyy[x + i]);
    }
    oxx[x] = sxx;
    oxy[x] = sxy;
    oyy[x] = syy;
  }
}

// Vertical blur of the ring rows (rows[j] holds image row y - R + j) and the response
// det - k trace^2 into out (columns x0 .. x1 - 1).
template <int R>
void response_row(const float* const* rxx, const float* const* rxy, const float* const* ryy,
                  const float* kern, float harris_k, int x0, int x1, float* __restrict out) {
  float k[R + 1];
  for (int i = 0; i <= R; ++i) {
    k[i] = kern[R + i];
  }
  for (int x = x0; x < x1; ++x) {
    float sxx = k[0] * rxx[R][x];
    float sxy = k[0] * rxy[R][x];
    float syy = k[0] * ryy[R][x];
    for (int i = 1; i <= R; ++i) {
      sxx += k[i] * (rxx[R - i][x] + rxx[R + i][x]);
      sxy += k[i] * (rxy[R - i][x] + rxy[R + i][x]);
      syy += k[i] * (ryy[R - i][x] + ryy[R + i][x]);
    }
    const float tr = sxx + syy;
    out[x] = sxx * syy - sxy * sxy - harris_k * tr * tr;
  }
}

template <int R>
void harris_response(const hal::GrayImageView& image, const float* kern, float harris_k,
                     HarrisDetector::Planes& p, int row_begin, int row_end);

}  // namespace

HarrisDetector::HarrisDetector(const HarrisConfig& config)
    : config_(config), planes_(std::make_unique<Planes>()) {
  config_.max_corners = std::clamp(config_.max_corners, 0, hal::kMaxCorners);
  const float sigma = std::clamp(config_.sigma_px, 0.3F, 1.5F);
  config_.sigma_px = sigma;
  kernel_radius_ = std::clamp(static_cast<int>(std::ceil(2.0F * sigma)), 1, 3);
  float sum = 0.0F;
  for (int j = 0; j <= 2 * kernel_radius_; ++j) {
    const int i = j - kernel_radius_;  // offset from the centre
    const float w = std::exp(-static_cast<float>(i * i) / (2.0F * sigma * sigma));
    kernel_[static_cast<std::size_t>(j)] = w;
    sum += w;
  }
  for (int i = 0; i <= 2 * kernel_radius_; ++i) {
    kernel_[static_cast<std::size_t>(i)] /= sum;
  }
}

HarrisDetector::~HarrisDetector() = default;

ImageCheck HarrisDetector::detect(const hal::GrayImageView& image, int width, int height) {
  const ImageCheck check = begin(image, width, height);
  if (check == ImageCheck::kOk) {
    while (!step(height)) {
    }
  }
  return check;
}

ImageCheck HarrisDetector::begin(const hal::GrayImageView& image, int width, int height) {
  corner_count_ = 0;
  max_response_ = 0.0F;
  const ImageCheck check = check_image(image, width, height);
  image_ = check == ImageCheck::kOk ? image : hal::GrayImageView{};
  nms_row_ = 0;
  candidate_count_ = 0;
  next_row_ = check == ImageCheck::kOk ? 1 : height;
  finished_ = check != ImageCheck::kOk;
  return check;
}

bool HarrisDetector::step(int max_rows) {
  if (finished_) {
    return true;
  }
  Planes& p = *planes_;
  const int h = image_.height;
  const int end = std::min(h - 1, next_row_ + std::max(1, max_rows));
  switch (kernel_radius_) {
    case 1:
      harris_response<1>(image_, kernel_.data(), config_.k, p, next_row_, end);
      break;
    case 2:
      harris_response<2>(image_, kernel_.data(), config_.k, p, next_row_, end);
      break;
    default:
      harris_response<3>(image_, kernel_.data(), config_.k, p, next_row_, end);
      break;
  }
  next_row_ = end;
  // Response rows up to end - 1 - R are complete; suppression of a row needs the next one.
  suppress_rows(end - 1 - kernel_radius_);
  if (next_row_ < h - 1) {
    return false;
  }
  select_corners();
  finished_ = true;
  return true;
}

// 3x3 non-maximum suppression above the absolute floor of rows nms_row_ .. last_response_row - 1;
// ties go to the first pixel in scan order. The relative threshold needs the strongest response
// of the frame: select_corners() applies it.
void HarrisDetector::suppress_rows(int last_response_row) {
  Planes& p = *planes_;
  const int w = image_.width;
  const int h = image_.height;
  const int border = std::max(config_.border_px, kernel_radius_ + 2);
  const float floor_response = config_.min_response;
  const int capacity = static_cast<int>(p.candidates.size());
  nms_row_ = std::max(nms_row_, border);
  const int y_end = std::min(h - border, last_response_row);
  float max_r = max_response_;
  int n = candidate_count_;
  for (; nms_row_ < y_end && n < capacity; ++nms_row_) {
    const int y = nms_row_;
    const float* up = p.response.data() + static_cast<std::ptrdiff_t>(y - 1) * w;
    const float* mid = p.response.data() + static_cast<std::ptrdiff_t>(y) * w;
    const float* dn = p.response.data() + static_cast<std::ptrdiff_t>(y + 1) * w;
    for (int x = border; x < w - border; ++x) {
      const float v = mid[x];
      if (v <= floor_response) {
        continue;
      }
      if (v > up[x - 1] && v > up[x] && v > up[x + 1] && v > mid[x - 1] && v >= mid[x + 1] &&
          v >= dn[x - 1] && v >= dn[x] && v >= dn[x + 1]) {
        p.candidates[static_cast<std::size_t>(n)] = {static_cast<double>(x), static_cast<double>(y),
                                                     v};
        max_r = std::max(max_r, v);
        if (++n == capacity) {
          break;
        }
      }
    }
  }
  max_response_ = max_r;
  candidate_count_ = n;
}

void HarrisDetector::select_corners() {
  Planes& p = *planes_;
  const float floor_response = config_.min_response;
  const float max_r = max_response_;
  int n = candidate_count_;
  const float threshold = std::max(floor_response, config_.quality_level * max_r);
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    if (p.candidates[static_cast<std::size_t>(i)].response > threshold) {
      p.candidates[static_cast<std::size_t>(kept++)] = p.candidates[static_cast<std::size_t>(i)];
    }
  }
  n = kept;

  const auto stronger = [](const Corner& a, const Corner& b) { return a.response > b.response; };
  Corner* first = p.candidates.data();
  if (n > kMaxSortedCandidates) {
    std::nth_element(first, first + kMaxSortedCandidates, first + n, stronger);
    n = kMaxSortedCandidates;
  }
  std::sort(first, first + n, stronger);

  // Strongest first, at least min_distance from every accepted corner.
  const double d2 =
      static_cast<double>(config_.min_distance_px) * static_cast<double>(config_.min_distance_px);
  for (int i = 0; i < n && corner_count_ < config_.max_corners; ++i) {
    const Corner& c = first[i];
    bool free = true;
    for (int j = 0; j < corner_count_; ++j) {
      const double dx = corners_[static_cast<std::size_t>(j)].x - c.x;
      const double dy = corners_[static_cast<std::size_t>(j)].y - c.y;
      if (dx * dx + dy * dy < d2) {
        free = false;
        break;
      }
    }
    if (free) {
      corners_[static_cast<std::size_t>(corner_count_++)] = c;
    }
  }
}

namespace {

template <int R>
void harris_response(const hal::GrayImageView& image, const float* kern, float harris_k,
                     HarrisDetector::Planes& p, int row_begin, int row_end) {
  constexpr int kRing = HarrisDetector::Planes::kRing;
  const int w = image.width;
  const int h = image.height;
  const float* rxx[2 * R + 1];
  const float* rxy[2 * R + 1];
  const float* ryy[2 * R + 1];
  // Image row yi (1 .. h-2) goes to ring slot yi % kRing; response row y = yi - R is ready once
  // rows y - R .. y + R are in.
  for (int yi = std::max(row_begin, 1); yi < std::min(row_end, h - 1); ++yi) {
    const int slot = (yi % kRing) * hal::kImageWidth;
    blurred_products_row<R>(image, yi, kern, p.gxx.data(), p.gxy.data(), p.gyy.data(),
                            p.hxx.data() + slot, p.hxy.data() + slot, p.hyy.data() + slot);
    const int y = yi - R;
    if (y < 1 + R) {
      continue;
    }
    for (int j = 0; j <= 2 * R; ++j) {
      const int s = ((y - R + j) % kRing) * hal::kImageWidth;
      rxx[j] = p.hxx.data() + s;
      rxy[j] = p.hxy.data() + s;
      ryy[j] = p.hyy.data() + s;
    }
    response_row<R>(rxx, rxy, ryy, kern, harris_k, 1 + R, w - 1 - R,
                    p.response.data() + static_cast<std::ptrdiff_t>(y) * w);
  }
}

}  // namespace

}  // namespace cleanslam::slam_core::frontend
