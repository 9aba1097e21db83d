#pragma once

#include <Eigen/Core>

#include "cleanslam/paper_models/landmark_model.hpp"
#include "cleanslam/paper_models/ray_gaussian.hpp"

namespace cleanslam::paper_models {

// Measurement of an XYZ landmark in the image plane: h = project(C_cw (y - p)) and its Jacobian
// d h / d y (eq. 32 with the pose known). False when the landmark is not in front of the camera.
bool image_plane_measurement(const Pinhole& camera, const KnownPose& pose,
                             const Eigen::Vector3d& y_w, Eigen::Vector2d& h,
                             Eigen::Matrix<double, 2, 3>& H);

struct ConventionalParams {
  Pinhole camera;
  double assumed_depth = 10.0;  // m
  double sigma_along = 1000.0;  // m, ε_ct of the initialization
  double sigma_across = 0.005;  // m, ε_cn of the initialization
  double sigma_px = 0.1;        // pixel noise of the update
};

// The conventional image-plane model: initialized like the proposed one (eq. 12-20, 39-40), then
// updated in pixels.
class ConventionalModel final : public LandmarkModel {
 public:
  explicit ConventionalModel(const ConventionalParams& params) : params_(params) {}

  ModelStatus initialize(const KnownPose& pose, const Eigen::Vector2d& pixel) override;
  ModelStatus update(const KnownPose& pose, const Eigen::Vector2d& pixel) override;
  Eigen::Vector3d position_w() const override { return state_.mean; }
  Eigen::Matrix3d covariance_w() const override { return state_.covariance; }

 private:
  ConventionalParams params_;
  Gaussian3 state_;
  bool initialized_ = false;
};

}  // namespace cleanslam::paper_models
