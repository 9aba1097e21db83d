#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/paper_models/comparison_scenario.hpp"
#include "cleanslam/paper_models/landmark_model.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/ekf_config.hpp"
#include "cleanslam/slam_core/odometry_increment.hpp"

// The paper's model (Sections 2.4 and 3.1) for the comparison scenarios, run through the real Ekf.
namespace cleanslam::paper_models {

struct ProposedParams {
  Pinhole camera;
  double eps_ct = 1000.0;       // m, eq. 14-15
  double eps_cn = 0.005;        // m, at the assumed depth (eq. 16 with ε_cal = 0)
  double assumed_depth = 10.0;  // m, eq. 13
  double gate_chi2 = 1e12;      // the paper's simulations have no gate (the pixel gate is off)
};

// A 320x240 calibration of the pinhole (no distortion) for the Ekf.
hal::Calibration pinhole_calibration(const Pinhole& camera);
slam_core::EkfConfig proposed_config(const ProposedParams& params);
slam_core::Vector6d camera_pose_vector(const KnownPose& pose);
// The odometry increment of a pure translation from one pose to the next (eq. 3 with no rotation).
slam_core::OdometryIncrement translation_increment(const KnownPose& from, const KnownPose& to);

// One landmark in an Ekf built with proposed_config(): initialize() resets the filter to the pose
// (zero covariance), update() predicts to the new pose and fuses the pixel. Poses must differ by
// a translation only.
class ProposedModel final : public LandmarkModel {
 public:
  explicit ProposedModel(slam_core::Ekf& ekf) : ekf_(ekf) {}

  ModelStatus initialize(const KnownPose& pose, const Eigen::Vector2d& pixel) override;
  ModelStatus update(const KnownPose& pose, const Eigen::Vector2d& pixel) override;
  Eigen::Vector3d position_w() const override;
  Eigen::Matrix3d covariance_w() const override;

 private:
  slam_core::Ekf& ekf_;
  KnownPose pose_;
  int slot_ = -1;
};

// Fig. 7-8: the landmarks initialized together from the first pose, one update from the second.
struct BatchResult {
  std::array<Eigen::Vector3d, kFig8Landmarks> estimate{};
  std::array<Eigen::Matrix3d, kFig8Landmarks> covariance{};
  int fused = 0;
  double rms = 0.0;  // RMS of |estimate - truth| over the landmarks
};
BatchResult proposed_one_step_batch(slam_core::Ekf& ekf, const Pinhole& camera,
                                    const KnownPose& first, const KnownPose& second,
                                    const std::array<Eigen::Vector3d, kFig8Landmarks>& landmarks);

// Fig. 9: noisy tracking and yaw, the full filter with an uncertain pose.
struct NoisyRunParams {
  Pinhole camera;
  double pixel_noise_px = 0.2;
  double yaw_noise_rad = 0.1 * 3.14159265358979323846 / 180.0;  // per step
  double step = 0.15;                                           // m forward per frame
  int steps = 10;                                               // frames after the first
};
struct NoisyRunResult {
  bool completed = false;  // every landmark initialized and every prediction applied
  double rms = 0.0;        // RMS landmark error after the last frame, over all landmarks
  int rejected = 0;        // observations the filter did not fuse
};
NoisyRunResult proposed_noisy_run(slam_core::Ekf& ekf, const NoisyRunParams& params,
                                  const std::array<Eigen::Vector3d, kFig8Landmarks>& landmarks,
                                  std::uint32_t seed);

}  // namespace cleanslam::paper_models
