#pragma once

#include <span>

#include <Eigen/Core>

#include "cleanslam/slam_core/geometry.hpp"

// The planar camera pose (x, y, yaw) that best explains one frame's sightings of mapped landmarks
// together with the pose's prior: Gauss-Newton on the negative log-posterior, each landmark held
// at its estimate with its covariance added to the sighting's noise (z, roll and pitch stay at the
// prior's). The EKF linearizes an update there when the prior's pose is too uncertain for the
// measurement's linearization (Ekf::update).
namespace cleanslam::slam_core {

// A sighting with its landmark's prior conditioned on the planar pose q = (x, y, yaw): the
// landmark's mean y + G (q - q0) and covariance Pyy (the Gaussian conditional given q). A landmark
// mapped from the pose itself moves with it and tells the solve nothing the prior did not.
struct PoseSighting {
  Eigen::Vector3d y = Eigen::Vector3d::Zero();    // landmark mean at the prior pose q0, world
  Eigen::Matrix3d G = Eigen::Matrix3d::Zero();    // d y / d q
  Eigen::Matrix3d Pyy = Eigen::Matrix3d::Zero();  // covariance given q
  Eigen::Vector3d ct = Eigen::Vector3d::UnitX();  // measured ray, camera frame (eq. 12)
};

struct SightingNoise {
  double eps_ct_m = 30.0;   // eq. 14-15
  double eps_px = 0.7;      // eq. 16: sqrt(eps_trk^2 + eps_cal^2)
  double focal_px = 250.0;  // f_p
  double min_depth_m = 0.05;
};

// z - h of eq. 13 and 21 with z taken at the predicted depth along the measured ray: the predicted
// camera point's component across the ray, (c c^T - I) h, c = ct / |ct|. With the Jacobians, its
// derivatives on the pose's (x, y, yaw) and on the landmark.
Eigen::Vector3d sighting_residual(const Vector6d& camera_pose, const Eigen::Vector3d& y,
                                  const Eigen::Vector3d& ct, Eigen::Matrix3d* J_planar = nullptr,
                                  Eigen::Matrix3d* J_landmark = nullptr);

// The residual's covariance for a landmark at y: its covariance Pyy in the camera frame plus eq.
// 14's R_v at the predicted depth; false for a landmark at most min_depth_m ahead along the ray.
bool sighting_covariance(const Vector6d& camera_pose, const Eigen::Vector3d& y,
                         const PoseSighting& s, const SightingNoise& noise, Eigen::Matrix3d& S);

// The sighting's landmark mean at pose's (x, y, yaw).
Eigen::Vector3d conditional_landmark(const PoseSighting& s, const Vector6d& prior_pose,
                                     const Vector6d& camera_pose);

// Minimizes (p - p0)^T P0^-1 (p - p0) + sum r_j^T S_j^-1 r_j over p = (x, y, yaw) from the prior
// pose p0 (P0: the prior's 3x3 covariance of x, y, yaw), sightings ahead of the camera only.
// Writes the pose and returns true when the iteration converged to finite values with at least
// one sighting; pose untouched otherwise.
// fit: the solution's prior term, its sightings' term and their count (each sighting's residual
// has two degrees of freedom across the ray).
struct PoseFit {
  double prior_cost = 0.0;
  double sightings_cost = 0.0;
  int sightings = 0;
};
bool solve_planar_pose(const Vector6d& prior_pose, const Eigen::Matrix3d& P0,
                       std::span<const PoseSighting> sightings, const SightingNoise& noise,
                       Vector6d& pose, PoseFit& fit, int max_iterations = 20);

}  // namespace cleanslam::slam_core
