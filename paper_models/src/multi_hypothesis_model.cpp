#include "cleanslam/paper_models/multi_hypothesis_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cleanslam/paper_models/conventional_model.hpp"
#include "cleanslam/paper_models/pixel_update.hpp"

namespace cleanslam::paper_models {

HypothesisLayout hypothesis_layout(std::size_t count, double depth_min, double depth_max) {
  HypothesisLayout layout;
  layout.count = std::clamp<std::size_t>(count, 1, kMaxHypotheses);
  const double span = depth_max / depth_min;
  if (layout.count == 1) {
    const double alpha = (span - 1.0) / (span + 1.0);
    layout.depth[0] = std::sqrt(depth_min * depth_max);
    layout.sigma_along[0] = alpha * layout.depth[0];
    return layout;
  }
  const double beta = std::pow(span, 1.0 / static_cast<double>(layout.count - 1));
  const double alpha = (beta - 1.0) / (beta + 1.0);
  for (std::size_t i = 0; i < layout.count; ++i) {
    layout.depth[i] = depth_min * std::pow(beta, static_cast<double>(i));
    layout.sigma_along[i] = alpha * layout.depth[i];
  }
  return layout;
}

ModelStatus MultiHypothesisModel::initialize(const KnownPose& pose, const Eigen::Vector2d& pixel) {
  if (!is_finite(pose) || !pixel.allFinite()) {
    return counted(ModelStatus::kNonFiniteInput);
  }
  const HypothesisLayout layout =
      hypothesis_layout(params_.hypotheses, params_.depth_min, params_.depth_max);
  count_ = layout.count;
  for (std::size_t i = 0; i < count_; ++i) {
    const double sigma_across = layout.depth[i] * params_.sigma_px / params_.camera.f_px;
    hypotheses_[i] = ray_gaussian_w(params_.camera, pose, pixel, layout.depth[i],
                                    layout.sigma_along[i], sigma_across);
    weights_[i] = 1.0 / static_cast<double>(count_);
  }
  return ModelStatus::kOk;
}

ModelStatus MultiHypothesisModel::update(const KnownPose& pose, const Eigen::Vector2d& pixel) {
  if (count_ == 0) {
    return counted(ModelStatus::kNotInitialized);
  }
  if (!is_finite(pose) || !pixel.allFinite()) {
    return counted(ModelStatus::kNonFiniteInput);
  }
  std::array<Gaussian3, kMaxHypotheses> next{};
  std::array<double, kMaxHypotheses> log_weight{};
  std::size_t kept = 0;
  double max_log_weight = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < count_; ++i) {
    Eigen::Vector2d h;
    Eigen::Matrix<double, 2, 3> H;
    if (!image_plane_measurement(params_.camera, pose, hypotheses_[i].mean, h, H)) {
      continue;
    }
    Gaussian3 g = hypotheses_[i];
    double log_likelihood = 0.0;
    if (pixel_update<3>(g.mean, g.covariance, h, H, pixel, params_.sigma_px, &log_likelihood) !=
            ModelStatus::kOk ||
        !g.mean.allFinite() || !g.covariance.allFinite() || !std::isfinite(log_likelihood)) {
      continue;
    }
    next[kept] = g;
    log_weight[kept] = std::log(weights_[i]) + log_likelihood;
    max_log_weight = std::max(max_log_weight, log_weight[kept]);
    ++kept;
  }
  if (kept == 0) {
    return counted(ModelStatus::kBehindCamera);
  }
  double total = 0.0;
  for (std::size_t i = 0; i < kept; ++i) {
    log_weight[i] = std::exp(log_weight[i] - max_log_weight);
    total += log_weight[i];
  }
  count_ = 0;
  double kept_total = 0.0;
  for (std::size_t i = 0; i < kept; ++i) {
    const double w = log_weight[i] / total;
    if (w < params_.prune_weight) {
      continue;
    }
    hypotheses_[count_] = next[i];
    weights_[count_] = w;
    kept_total += w;
    ++count_;
  }
  for (std::size_t i = 0; i < count_; ++i) {
    weights_[i] /= kept_total;
  }
  return ModelStatus::kOk;
}

Eigen::Vector3d MultiHypothesisModel::position_w() const {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < count_; ++i) {
    mean += weights_[i] * hypotheses_[i].mean;
  }
  return mean;
}

Eigen::Matrix3d MultiHypothesisModel::covariance_w() const {
  const Eigen::Vector3d mean = position_w();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < count_; ++i) {
    const Eigen::Vector3d d = hypotheses_[i].mean - mean;
    covariance += weights_[i] * (hypotheses_[i].covariance + d * d.transpose());
  }
  return covariance;
}

}  // namespace cleanslam::paper_models
