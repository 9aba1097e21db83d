#include "cleanslam/slam_core/frontend/harris.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace cleanslam::slam_core::frontend {

namespace {
constexpr int kPlaneSize = hal::kImageWidth * hal::kImageHeight;
// Candidates sorted by response before the minimum-distance pass.
constexpr int kMaxSortedCandidates = 4 * hal::kMaxCorners;
}  // namespace

struct HarrisDetector::Planes {
  // Horizontally blurred structure-tensor products, then the response.
  std::array<float, kPlaneSize> hxx;
  std::array<float, kPlaneSize> hxy;
  std::array<float, kPlaneSize> hyy;
  std::array<float, kPlaneSize> response;
  std::array<float, hal::kImageWidth> gxx;
  std::array<float, hal::kImageWidth> gxy;
  std::array<float, hal::kImageWidth> gyy;
  std::array<Corner, kPlaneSize / 4 + hal::kImageWidth> candidates;
};

HarrisDetector::HarrisDetector(const HarrisConfig& config)
    : config_(config), planes_(std::make_unique<Planes>()) {
  config_.max_corners = std::clamp(config_.max_corners, 0, hal::kMaxCorners);
  const float sigma = std::clamp(config_.sigma_px, 0.3F, 1.5F);
  config_.sigma_px = sigma;
  kernel_radius_ = std::clamp(static_cast<int>(std::ceil(2.0F * sigma)), 1, 3);
  float sum = 0.0F;
  for (int i = -kernel_radius_; i <= kernel_radius_; ++i) {
    const float w = std::exp(-static_cast<float>(i * i) / (2.0F * sigma * sigma));
    kernel_[static_cast<std::size_t>(i + kernel_radius_)] = w;
    sum += w;
  }
  for (int i = 0; i <= 2 * kernel_radius_; ++i) {
    kernel_[static_cast<std::size_t>(i)] /= sum;
  }
}

HarrisDetector::~HarrisDetector() = default;

ImageCheck HarrisDetector::detect(const hal::GrayImageView& image, int width, int height) {
  corner_count_ = 0;
  max_response_ = 0.0F;
  const ImageCheck check = check_image(image, width, height);
  if (check != ImageCheck::kOk) {
    return check;
  }
  Planes& p = *planes_;
  const int w = width;
  const int h = height;
  const int r = kernel_radius_;
  const float* kern = kernel_.data();

  // Sobel gradients and their products, blurred along each row (rows 1..h-2).
  for (int y = 1; y < h - 1; ++y) {
    const std::uint8_t* a = image.row(y - 1);
    const std::uint8_t* b = image.row(y);
    const std::uint8_t* c = image.row(y + 1);
    float* gxx = p.gxx.data();
    float* gxy = p.gxy.data();
    float* gyy = p.gyy.data();
    for (int x = 1; x < w - 1; ++x) {
      const int gx = (a[x + 1] - a[x - 1]) + 2 * (b[x + 1] - b[x - 1]) + (c[x + 1] - c[x - 1]);
      const int gy = (c[x - 1] - a[x - 1]) + 2 * (c[x] - a[x]) + (c[x + 1] - a[x + 1]);
      const auto fx = static_cast<float>(gx);
      const auto fy = static_cast<float>(gy);
      gxx[x] = fx * fx;
      gxy[x] = fx * fy;
      gyy[x] = fy * fy;
    }
    float* oxx = p.hxx.data() + y * w;
    float* oxy = p.hxy.data() + y * w;
    float* oyy = p.hyy.data() + y * w;
    for (int x = 1 + r; x < w - 1 - r; ++x) {
      float sxx = 0.0F;
      float sxy = 0.0F;
      float syy = 0.0F;
      for (int k = -r; k <= r; ++k) {
        const float wk = kern[k + r];
        sxx += wk * gxx[x + k];
        sxy += wk * gxy[x + k];
        syy += wk * gyy[x + k];
      }
      oxx[x] = sxx;
      oxy[x] = sxy;
      oyy[x] = syy;
    }
  }

  // Vertical blur and the response det - k trace^2, on the rows and columns where it is valid.
  const int x0 = 1 + r;
  const int x1 = w - 1 - r;
  const int y0 = 1 + r;
  const int y1 = h - 1 - r;
  const float k = config_.k;
  float max_r = 0.0F;
  for (int y = y0; y < y1; ++y) {
    float* out = p.response.data() + y * w;
    for (int x = x0; x < x1; ++x) {
      float sxx = 0.0F;
      float sxy = 0.0F;
      float syy = 0.0F;
      for (int j = -r; j <= r; ++j) {
        const float wj = kern[j + r];
        const int idx = (y + j) * w + x;
        sxx += wj * p.hxx[static_cast<std::size_t>(idx)];
        sxy += wj * p.hxy[static_cast<std::size_t>(idx)];
        syy += wj * p.hyy[static_cast<std::size_t>(idx)];
      }
      const float tr = sxx + syy;
      const float resp = sxx * syy - sxy * sxy - k * tr * tr;
      out[x] = resp;
      max_r = std::max(max_r, resp);
    }
  }
  max_response_ = max_r;
  const float threshold = std::max(config_.min_response, config_.quality_level * max_r);
  if (!(max_r > threshold)) {
    return ImageCheck::kOk;
  }

  // 3x3 non-maximum suppression; ties go to the first pixel in scan order.
  const int border = std::max(config_.border_px, r + 2);
  int n = 0;
  const int capacity = static_cast<int>(p.candidates.size());
  for (int y = border; y < h - border && n < capacity; ++y) {
    const float* up = p.response.data() + (y - 1) * w;
    const float* mid = p.response.data() + y * w;
    const float* dn = p.response.data() + (y + 1) * w;
    for (int x = border; x < w - border; ++x) {
      const float v = mid[x];
      if (v <= threshold) {
        continue;
      }
      if (v > up[x - 1] && v > up[x] && v > up[x + 1] && v > mid[x - 1] && v >= mid[x + 1] &&
          v >= dn[x - 1] && v >= dn[x] && v >= dn[x + 1]) {
        p.candidates[static_cast<std::size_t>(n)] = {static_cast<double>(x), static_cast<double>(y),
                                                     v};
        if (++n == capacity) {
          break;
        }
      }
    }
  }

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
  return ImageCheck::kOk;
}

}  // namespace cleanslam::slam_core::frontend
