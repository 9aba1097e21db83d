#pragma once

// A pixel-space stand-in for the EKF behind frontend::LandmarkEstimator: landmarks are points of
// the synthetic texture plane; the "camera" is a similarity warp. The estimator believes the
// warp `belief`, which the test sets to the true warp plus a common error. Depth scales inversely
// with the warp's scale (2 m at scale 1).
#include <array>
#include <cmath>
#include <cstddef>
#include <span>

#include <Eigen/Core>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/slam_core/frontend/landmark_estimator.hpp"
#include "frontend_synthetic.hpp"

namespace cleanslam::test {

class FakeEstimator : public slam_core::frontend::LandmarkEstimator {
 public:
  Warp belief;
  // The true warp, set by the test: a landmark's true texture point is taken through it.
  Warp truth;
  double sigma_common_px = 4.0;
  double sigma_pixel_px = 1.0;
  int updates = 0;
  int fused_total = 0;
  int last_fused = 0;
  int deletions = 0;
  int initializations = 0;
  // Next slot initialize_landmark hands out is the lowest free one; -1 when all are used.
  int capacity = hal::kMaxLandmarks;

  // Moves a landmark's texture point (the estimator's belief about it), in texture pixels.
  struct Nudge {
    int slot;
    double dx;
    double dy;
  };
  void nudge(const Nudge& n) {
    tx_[static_cast<std::size_t>(n.slot)] += n.dx;
    ty_[static_cast<std::size_t>(n.slot)] += n.dy;
  }

  bool used(int slot) const { return used_[static_cast<std::size_t>(slot)]; }
  int used_count() const {
    int n = 0;
    for (bool u : used_) {
      n += u ? 1 : 0;
    }
    return n;
  }
  // Where a landmark really is on the texture.
  void true_texture_point(int slot, double& x, double& y) const {
    x = true_x_[static_cast<std::size_t>(slot)];
    y = true_y_[static_cast<std::size_t>(slot)];
  }
  // The texture point the estimator believes a landmark is at.
  void texture_point(int slot, double& x, double& y) const {
    x = tx_[static_cast<std::size_t>(slot)];
    y = ty_[static_cast<std::size_t>(slot)];
  }

  bool predict_pixel(int slot, slam_core::frontend::PixelPrediction& out) override {
    if (slot < 0 || slot >= hal::kMaxLandmarks || !used(slot)) {
      return false;
    }
    double u = 0.0;
    double v = 0.0;
    belief.apply(tx_[static_cast<std::size_t>(slot)], ty_[static_cast<std::size_t>(slot)], u, v);
    out.uv = {u, v};
    const double var = sigma_common_px * sigma_common_px + sigma_pixel_px * sigma_pixel_px;
    out.S = Eigen::Matrix2d::Identity() * var;
    out.depth_m = 2.0 / belief.scale;
    out.in_front = true;
    return true;
  }

  int joint_pixel_innovation(std::span<const slam_core::frontend::PixelObservation> obs,
                             std::span<double> nu, std::span<double> S) override {
    const auto count = static_cast<int>(obs.size());
    if (count > hal::kMaxObservationsPerFrame || nu.size() < 2 * obs.size() ||
        S.size() < 4 * obs.size() * obs.size()) {
      return -1;
    }
    const int n = 2 * count;
    for (int i = 0; i < count; ++i) {
      slam_core::frontend::PixelPrediction p;
      const auto& o = obs[static_cast<std::size_t>(i)];
      if (!predict_pixel(o.slot, p)) {
        return -1;
      }
      nu[static_cast<std::size_t>(2 * i)] = o.u_px - p.uv.x();
      nu[static_cast<std::size_t>(2 * i + 1)] = o.v_px - p.uv.y();
    }
    for (int c = 0; c < n; ++c) {
      for (int r = 0; r < n; ++r) {
        double s = (r % 2 == c % 2) ? sigma_common_px * sigma_common_px : 0.0;
        if (r == c) {
          s += sigma_pixel_px * sigma_pixel_px;
        }
        S[static_cast<std::size_t>(c * n + r)] = s;
      }
    }
    return count;
  }

  int initialize_landmark(double u_px, double v_px) override {
    for (int s = 0; s < capacity; ++s) {
      if (!used(s)) {
        used_[static_cast<std::size_t>(s)] = true;
        belief.invert(u_px, v_px, tx_[static_cast<std::size_t>(s)],
                      ty_[static_cast<std::size_t>(s)]);
        truth.invert(u_px, v_px, true_x_[static_cast<std::size_t>(s)],
                     true_y_[static_cast<std::size_t>(s)]);
        ++initializations;
        return s;
      }
    }
    return -1;
  }

  void delete_landmark(int slot) override {
    if (slot >= 0 && slot < hal::kMaxLandmarks && used(slot)) {
      used_[static_cast<std::size_t>(slot)] = false;
      ++deletions;
    }
  }

  int update(const slam_core::frontend::PixelObservation* /*obs*/, int count) override {
    ++updates;
    fused_total += count;
    last_fused = count;
    return count;
  }

 private:
  std::array<bool, hal::kMaxLandmarks> used_{};
  std::array<double, hal::kMaxLandmarks> tx_{};
  std::array<double, hal::kMaxLandmarks> ty_{};
  std::array<double, hal::kMaxLandmarks> true_x_{};
  std::array<double, hal::kMaxLandmarks> true_y_{};
};

}  // namespace cleanslam::test
