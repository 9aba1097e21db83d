#include "cleanslam/paper_models/comparison_scenario.hpp"

#include <cmath>
#include <numbers>
#include <random>

namespace cleanslam::paper_models {

Eigen::Vector3d landmark_w(const KnownPose& pose, const LandmarkDirection& direction,
                           double range) {
  const double ce = std::cos(direction.elevation);
  const Eigen::Vector3d ray_c{ce * std::cos(direction.azimuth), ce * std::sin(direction.azimuth),
                              std::sin(direction.elevation)};
  return pose.position_w + range * (pose.C_wc * ray_c);
}

KnownPose moved_pose(const KnownPose& pose, Motion motion, double distance) {
  KnownPose next = pose;
  const Eigen::Index axis = motion == Motion::kForward ? 0 : 1;
  next.position_w += distance * pose.C_wc.col(axis);
  return next;
}

bool observe(const Pinhole& camera, const KnownPose& pose, const Eigen::Vector3d& point_w,
             Eigen::Vector2d& pixel) {
  return project_c(camera, pose.C_wc.transpose() * (point_w - pose.position_w), pixel);
}

OneStepResult one_step(LandmarkModel& model, const Pinhole& camera, const KnownPose& first,
                       const KnownPose& second, const Eigen::Vector3d& landmark) {
  OneStepResult result;
  Eigen::Vector2d pixel;
  if (!observe(camera, first, landmark, pixel)) {
    result.status = ModelStatus::kBehindCamera;
    return result;
  }
  result.status = model.initialize(first, pixel);
  if (result.status == ModelStatus::kOk) {
    result.status = observe(camera, second, landmark, pixel) ? model.update(second, pixel)
                                                             : ModelStatus::kBehindCamera;
  }
  result.estimate_w = model.position_w();
  result.covariance_w = model.covariance_w();
  result.error = (result.estimate_w - landmark).norm();
  return result;
}

ComparisonSetup fig10_setup(Motion motion, double true_range) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  ComparisonSetup setup;
  setup.second = moved_pose(setup.first, motion, kFig10Motion);
  setup.landmark = landmark_w(setup.first, {22.0 * kDeg, 15.0 * kDeg}, true_range);
  return setup;
}

std::array<LandmarkDirection, kFig8Landmarks> fig8_directions(std::uint32_t seed) {
  std::mt19937 generator(seed);
  const auto uniform = [&generator](double half_width) {
    const double unit = static_cast<double>(generator()) / static_cast<double>(std::mt19937::max());
    return (2.0 * unit - 1.0) * half_width;
  };
  constexpr double kDeg = std::numbers::pi / 180.0;
  std::array<LandmarkDirection, kFig8Landmarks> directions{};
  for (auto& d : directions) {
    d.azimuth = uniform(25.0 * kDeg);
    d.elevation = uniform(15.0 * kDeg);
  }
  return directions;
}

}  // namespace cleanslam::paper_models
