#pragma once

#include <span>

#include <Eigen/Core>

#include "cleanslam/slam_core/frontend/search_region.hpp"

namespace cleanslam::slam_core::frontend {

// A pixel observation of a landmark slot (the layout of the EKF's Observation).
struct PixelObservation {
  int slot = -1;
  double u_px = 0.0;
  double v_px = 0.0;
};

// What the frame pipeline needs from the estimator: the EKF's landmark API, behind an interface
// so that the front end is built and tested without the EKF (an adapter wraps Ekf).
class LandmarkEstimator {
 public:
  virtual ~LandmarkEstimator() = default;
  // Predicted pixel, its 2x2 covariance and depth; false when the slot has no prediction.
  virtual bool predict_pixel(int slot, PixelPrediction& out) = 0;
  // Stacked innovations (2m, into nu) and their joint covariance (2m x 2m, column-major, into S),
  // m = obs.size(); returns m, or -1 (also when nu or S is too small).
  virtual int joint_pixel_innovation(std::span<const PixelObservation> obs, std::span<double> nu,
                                     std::span<double> S) = 0;
  // Undelayed initialization at a pixel; returns the slot (possibly one reused from a replaced
  // landmark) or -1.
  virtual int initialize_landmark(double u_px, double v_px) = 0;
  virtual void delete_landmark(int slot) = 0;
  // Fuses the observations; returns how many were fused. An estimator that bounds its work per
  // call may leave the update pending (update_pending()): continue_update() then does the rest,
  // one bounded part per call, and nothing else may be asked of it until the update is complete.
  virtual int update(const PixelObservation* obs, int count) = 0;
  [[nodiscard]] virtual bool update_pending() const { return false; }
  // One bounded part of a pending update; true when it is complete, with the count fused.
  virtual bool continue_update(int& fused) {
    fused = 0;
    return true;
  }
  // Position estimates in the world of the camera and of a landmark, for the patch scale (the
  // landmark's distance now and from where it was first seen); false when not available, and the
  // scale then falls back to the predicted depths.
  virtual bool camera_position(Eigen::Vector3d& /*out*/) { return false; }
  virtual bool landmark_position(int /*slot*/, Eigen::Vector3d& /*out*/) { return false; }
};

}  // namespace cleanslam::slam_core::frontend
