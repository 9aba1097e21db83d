#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/slam_core/frontend/landmark_estimator.hpp"

namespace cleanslam::tools::track {

// Stands in for the EKF when the front end runs alone: a landmark is its last pixel, predicted
// to move with the image's mean motion of the last frame (constant velocity in the image). The
// innovation covariance is a shared image motion (sigma_common, fully correlated between
// landmarks) plus independent pixel noise, so JCBB keeps the matches that agree on one motion.
// No depth is known: patches are matched at their first scale.
class ImageOnlyEstimator : public slam_core::frontend::LandmarkEstimator {
 public:
  struct Config {
    double sigma_common_px = 12.0;
    double sigma_pixel_px = 1.5;
  };

  explicit ImageOnlyEstimator(const Config& config) : config_(config) {}

  bool predict_pixel(int slot, slam_core::frontend::PixelPrediction& out) override;
  int joint_pixel_innovation(std::span<const slam_core::frontend::PixelObservation> obs,
                             std::span<double> nu, std::span<double> S) override;
  int initialize_landmark(double u_px, double v_px) override;
  void delete_landmark(int slot) override;
  int update(const slam_core::frontend::PixelObservation* obs, int count) override;

  // Call after each frame: landmarks coast with the image motion when no update came.
  void end_frame();
  // A track id that is never reused (a slot is).
  [[nodiscard]] std::int64_t track_id(int slot) const;

 private:
  [[nodiscard]] bool used(int slot) const;

  Config config_;
  std::array<bool, hal::kMaxLandmarks> used_{};
  std::array<bool, hal::kMaxLandmarks> fresh_{};  // initialized in the current frame
  std::array<double, hal::kMaxLandmarks> u_{};
  std::array<double, hal::kMaxLandmarks> v_{};
  std::array<std::int64_t, hal::kMaxLandmarks> id_{};
  std::int64_t next_id_ = 0;
  double vel_u_ = 0.0;
  double vel_v_ = 0.0;
  bool updated_ = false;
};

}  // namespace cleanslam::tools::track
