#pragma once

#include <array>
#include <cstddef>

#include <Eigen/Core>

#include "cleanslam/paper_models/landmark_model.hpp"
#include "cleanslam/paper_models/ray_gaussian.hpp"

namespace cleanslam::paper_models {

inline constexpr std::size_t kMaxHypotheses = 32;

struct MultiHypothesisParams {
  Pinhole camera;
  std::size_t hypotheses = 5;
  double depth_min = 1.0;   // m
  double depth_max = 30.0;  // m
  double sigma_px = 0.1;
  double prune_weight = 1e-4;  // hypotheses whose normalized weight falls below this are removed
};

// Depths d_i = d_min β^i in geometric progression over [d_min, d_max] and the along-ray standard
// deviation α d_i with α = (β - 1) / (β + 1) (Kwok and Dissanayake; Sola et al.).
struct HypothesisLayout {
  std::array<double, kMaxHypotheses> depth{};
  std::array<double, kMaxHypotheses> sigma_along{};
  std::size_t count = 0;
};
HypothesisLayout hypothesis_layout(std::size_t count, double depth_min, double depth_max);

// A Gaussian sum of XYZ hypotheses along the first ray, each updated in the image plane and
// reweighted by its measurement likelihood; the estimate is the mixture's mean and covariance.
class MultiHypothesisModel final : public LandmarkModel {
 public:
  explicit MultiHypothesisModel(const MultiHypothesisParams& params) : params_(params) {}

  ModelStatus initialize(const KnownPose& pose, const Eigen::Vector2d& pixel) override;
  ModelStatus update(const KnownPose& pose, const Eigen::Vector2d& pixel) override;
  Eigen::Vector3d position_w() const override;
  Eigen::Matrix3d covariance_w() const override;

  std::size_t hypothesis_count() const { return count_; }
  const Gaussian3& hypothesis(std::size_t i) const { return hypotheses_[i]; }
  double weight(std::size_t i) const { return weights_[i]; }

 private:
  MultiHypothesisParams params_;
  std::array<Gaussian3, kMaxHypotheses> hypotheses_{};
  std::array<double, kMaxHypotheses> weights_{};
  std::size_t count_ = 0;
};

}  // namespace cleanslam::paper_models
