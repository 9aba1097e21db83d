#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "cleanslam/paper_models/landmark_model.hpp"

namespace cleanslam::paper_models {

// Direction of a landmark seen from a camera, in that camera's frame c: azimuth to the left of the
// optical axis, elevation upwards (rad).
struct LandmarkDirection {
  double azimuth = 0.0;
  double elevation = 0.0;
};

Eigen::Vector3d landmark_w(const KnownPose& pose, const LandmarkDirection& direction, double range);

enum class Motion : std::uint8_t { kForward, kLateral };

// The pose after translating by distance along the camera's x (forward) or y (left), without
// rotating.
KnownPose moved_pose(const KnownPose& pose, Motion motion, double distance);

// Noise-free pixel of a world point; false when it is not in front of the camera.
bool observe(const Pinhole& camera, const KnownPose& pose, const Eigen::Vector3d& point_w,
             Eigen::Vector2d& pixel);

struct OneStepResult {
  ModelStatus status = ModelStatus::kNotInitialized;
  Eigen::Vector3d estimate_w = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance_w = Eigen::Matrix3d::Zero();
  double error = 0.0;  // |estimate - truth|
};

// Section 4.1 and 4.3: initialize from the first pose, one noise-free update from the second.
OneStepResult one_step(LandmarkModel& model, const Pinhole& camera, const KnownPose& first,
                       const KnownPose& second, const Eigen::Vector3d& landmark);

// Section 4.3 (Fig. 10): a landmark at azimuth 22° and elevation 15° at the given range from the
// first pose (the world origin, camera looking along world x), seen again after 30 cm of motion.
struct ComparisonSetup {
  KnownPose first;
  KnownPose second;
  Eigen::Vector3d landmark = Eigen::Vector3d::Zero();
};
inline constexpr double kFig10Motion = 0.3;  // m
ComparisonSetup fig10_setup(Motion motion, double true_range);

// Fig. 7-8: ten directions with azimuth uniform in ±25° and elevation in ±15°, from a fixed seed.
inline constexpr std::size_t kFig8Landmarks = 10;
std::array<LandmarkDirection, kFig8Landmarks> fig8_directions(std::uint32_t seed);

}  // namespace cleanslam::paper_models
