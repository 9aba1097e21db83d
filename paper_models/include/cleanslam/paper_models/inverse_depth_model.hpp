#pragma once

#include <Eigen/Core>

#include "cleanslam/paper_models/landmark_model.hpp"

namespace cleanslam::paper_models {

// Civera, Davison, Montiel (2008): (x0, y0, z0, θ, φ, ρ), the first camera position, the ray's
// azimuth θ (about world z, from x) and elevation φ, and the inverse depth ρ.
using InverseDepthState = Eigen::Matrix<double, 6, 1>;

// Unit ray m(θ, φ) = (cos φ cos θ, cos φ sin θ, sin φ) in the world.
Eigen::Vector3d inverse_depth_ray_w(double azimuth, double elevation);

// y = x0 + m(θ, φ) / ρ and its Jacobian d y / d state.
Eigen::Vector3d inverse_depth_to_xyz(const InverseDepthState& s, Eigen::Matrix<double, 3, 6>* J);

// h = project(C_cw (ρ (x0 - p) + m(θ, φ))) and d h / d state (eq. 33 without the neglected terms).
bool inverse_depth_measurement(const Pinhole& camera, const KnownPose& pose,
                               const InverseDepthState& s, Eigen::Vector2d& h,
                               Eigen::Matrix<double, 2, 6>& H);

// Civera's linearity index L_d = 4 σ_d / d1 · |cos α| with σ_d = σ_ρ / ρ², d1 the distance from the
// camera and α the angle between m and the camera's ray to the point.
double inverse_depth_linearity_index(const KnownPose& pose, const InverseDepthState& s,
                                     const Eigen::Matrix<double, 6, 6>& P);

struct InverseDepthParams {
  Pinhole camera;
  double initial_inverse_depth = 0.1;  // 1/m
  double sigma_inverse_depth = 0.5;    // 1/m
  double sigma_px = 0.1;               // pixel noise; the ray angles start with std σ/f
  double linearity_threshold = 0.1;    // convert to XYZ below this index
};

class InverseDepthModel final : public LandmarkModel {
 public:
  explicit InverseDepthModel(const InverseDepthParams& params) : params_(params) {}

  ModelStatus initialize(const KnownPose& pose, const Eigen::Vector2d& pixel) override;
  ModelStatus update(const KnownPose& pose, const Eigen::Vector2d& pixel) override;
  Eigen::Vector3d position_w() const override;
  Eigen::Matrix3d covariance_w() const override;

  bool converted_to_xyz() const { return xyz_; }
  const InverseDepthState& inverse_depth_state() const { return state_; }

 private:
  InverseDepthParams params_;
  InverseDepthState state_ = InverseDepthState::Zero();
  Eigen::Matrix<double, 6, 6> P_ = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Vector3d y_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d Py_ = Eigen::Matrix3d::Zero();
  bool initialized_ = false;
  bool xyz_ = false;
};

}  // namespace cleanslam::paper_models
