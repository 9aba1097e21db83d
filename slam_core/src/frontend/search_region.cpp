#include "cleanslam/slam_core/frontend/search_region.hpp"

#include <algorithm>
#include <cmath>

namespace cleanslam::slam_core::frontend {

SearchRegion make_search_region(const PixelPrediction& prediction, int width, int height,
                                const SearchRegionConfig& config) {
  SearchRegion region;
  region.center = prediction.uv;
  region.gate_chi2 = config.gate_chi2;
  if (!prediction.in_front) {
    region.failure = RegionFailure::kNotInFront;
    return region;
  }
  if (!prediction.uv.allFinite() || !prediction.S.allFinite()) {
    region.failure = RegionFailure::kNonFinite;
    return region;
  }
  const double a = prediction.S(0, 0);
  const double d = prediction.S(1, 1);
  const double b = 0.5 * (prediction.S(0, 1) + prediction.S(1, 0));
  const double det = a * d - b * b;
  if (!(a > 0.0) || !(d > 0.0) || !(det > 0.0)) {
    region.failure = RegionFailure::kNotPositiveDefinite;
    return region;
  }
  region.S_inv << d / det, -b / det, -b / det, a / det;
  // Bounding box of the ellipse: half-widths sqrt(gate * S_xx), sqrt(gate * S_yy).
  const double hx = std::min(std::sqrt(config.gate_chi2 * a), config.max_half_extent_px);
  const double hy = std::min(std::sqrt(config.gate_chi2 * d), config.max_half_extent_px);
  const double lo = config.margin_px;
  const double hi_x = width - 1 - config.margin_px;
  const double hi_y = height - 1 - config.margin_px;
  region.x_min = std::max(prediction.uv.x() - hx, lo);
  region.x_max = std::min(prediction.uv.x() + hx, hi_x);
  region.y_min = std::max(prediction.uv.y() - hy, lo);
  region.y_max = std::min(prediction.uv.y() + hy, hi_y);
  if (region.x_min > region.x_max || region.y_min > region.y_max) {
    region.failure = RegionFailure::kOutsideImage;
    return region;
  }
  region.valid = true;
  return region;
}

}  // namespace cleanslam::slam_core::frontend
