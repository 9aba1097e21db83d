#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace cleanslam::slam_core::frontend {

// What the EKF predicts for one landmark (Ekf::predict_pixel): pixel, its 2x2 innovation
// covariance S, depth along the optical axis, and whether the landmark is in front of the camera.
struct PixelPrediction {
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  Eigen::Matrix2d S = Eigen::Matrix2d::Identity();
  double depth_m = 0.0;
  bool in_front = false;
};

struct SearchRegionConfig {
  // Chi-square bound of the gate, 2 degrees of freedom (9.21: 99 %).
  double gate_chi2 = 9.21;
  // The region's bounding box is at most this far from the prediction (bounded work).
  double max_half_extent_px = 40.0;
  // Patch centres keep this distance from the image border (a 15x15 window and one pixel for
  // interpolation).
  int margin_px = 8;
};

enum class RegionFailure : std::uint8_t {
  kNone,
  kNotInFront,
  kNonFinite,
  kNotPositiveDefinite,
  kOutsideImage,
};

// Section 3.3: the ellipse (x - uv)^T S^-1 (x - uv) <= gate around the predicted pixel, and its
// bounding box clipped to the part of the image where a patch fits.
struct SearchRegion {
  bool valid = false;
  RegionFailure failure = RegionFailure::kNone;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  Eigen::Matrix2d S_inv = Eigen::Matrix2d::Identity();
  double gate_chi2 = 0.0;
  double x_min = 0.0;
  double x_max = 0.0;
  double y_min = 0.0;
  double y_max = 0.0;

  [[nodiscard]] double mahalanobis2(double u, double v) const {
    const Eigen::Vector2d d(u - center.x(), v - center.y());
    return d.dot(S_inv * d);
  }
  [[nodiscard]] bool in_box(double u, double v) const {
    return u >= x_min && u <= x_max && v >= y_min && v <= y_max;
  }
  // Inside the gate and inside the searchable part of the image.
  [[nodiscard]] bool contains(double u, double v) const {
    return valid && in_box(u, v) && mahalanobis2(u, v) <= gate_chi2;
  }
};

[[nodiscard]] SearchRegion make_search_region(const PixelPrediction& prediction, int width,
                                              int height, const SearchRegionConfig& config = {});

}  // namespace cleanslam::slam_core::frontend
