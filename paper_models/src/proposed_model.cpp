#include "cleanslam/paper_models/proposed_model.hpp"

#include <cmath>
#include <limits>
#include <random>

#include "cleanslam/slam_core/geometry.hpp"

namespace cleanslam::paper_models {
namespace {

bool same_rotation(const KnownPose& a, const KnownPose& b) {
  return (a.C_wc - b.C_wc).cwiseAbs().maxCoeff() < 1e-12;
}

}  // namespace

hal::Calibration pinhole_calibration(const Pinhole& camera) {
  hal::Calibration calibration;
  calibration.camera.width = 320;
  calibration.camera.height = 240;
  calibration.camera.fx = camera.f_px;
  calibration.camera.fy = camera.f_px;
  calibration.camera.cx = camera.cx_px;
  calibration.camera.cy = camera.cy_px;
  calibration.camera.distortion = {0.0, 0.0, 0.0, 0.0};
  return calibration;
}

slam_core::EkfConfig proposed_config(const ProposedParams& params) {
  slam_core::EkfConfig config;
  config.eps_ct_m = params.eps_ct;
  config.assumed_depth_m = params.assumed_depth;
  config.eps_trk_px = params.eps_cn * params.camera.f_px / params.assumed_depth;
  config.eps_cal_px = 0.0;
  config.gate_chi2 = params.gate_chi2;
  config.gate_pixel_chi2 = 0.0;
  config.min_ray_motion_angle_rad = 0.0;
  // The pose is known exactly (zero variance): the PSD guard must accept a zero diagonal.
  config.min_variance = -std::numeric_limits<double>::denorm_min();
  return config;
}

slam_core::Vector6d camera_pose_vector(const KnownPose& pose) {
  slam_core::Vector6d x;
  x.head<3>() = pose.position_w;
  x.tail<3>() = slam_core::euler_zyx_from_rotation(pose.C_wc);
  return x;
}

slam_core::OdometryIncrement translation_increment(const KnownPose& from, const KnownPose& to) {
  slam_core::OdometryIncrement u;
  u.dx_c = from.C_wc.transpose() * (to.position_w - from.position_w);
  u.distance_m = u.dx_c.norm();
  u.dt_s = 1.0;
  return u;
}

ModelStatus ProposedModel::initialize(const KnownPose& pose, const Eigen::Vector2d& pixel) {
  if (!is_finite(pose) || !pixel.allFinite()) {
    return counted(ModelStatus::kNonFiniteInput);
  }
  if (!ekf_.reset(camera_pose_vector(pose), slam_core::Matrix6d::Zero())) {
    slot_ = -1;
    return counted(ModelStatus::kRejectedByFilter);
  }
  slot_ = ekf_.initialize_landmark(pixel.x(), pixel.y());
  pose_ = pose;
  return slot_ >= 0 ? ModelStatus::kOk : counted(ModelStatus::kRejectedByFilter);
}

ModelStatus ProposedModel::update(const KnownPose& pose, const Eigen::Vector2d& pixel) {
  if (slot_ < 0) {
    return counted(ModelStatus::kNotInitialized);
  }
  if (!is_finite(pose) || !pixel.allFinite()) {
    return counted(ModelStatus::kNonFiniteInput);
  }
  if (!same_rotation(pose_, pose)) {
    return counted(ModelStatus::kUnsupportedMotion);
  }
  if (!ekf_.predict(translation_increment(pose_, pose)).applied()) {
    return counted(ModelStatus::kRejectedByFilter);
  }
  pose_ = pose;
  const slam_core::Observation observation{slot_, pixel.x(), pixel.y()};
  const slam_core::UpdateStatus& status = ekf_.update(&observation, 1);
  if (status.fused != 1) {
    return counted(status.count > 0 && status.observations[0].result ==
                                           slam_core::ObservationResult::kBehindCamera
                       ? ModelStatus::kBehindCamera
                       : ModelStatus::kRejectedByFilter);
  }
  return ModelStatus::kOk;
}

Eigen::Vector3d ProposedModel::position_w() const {
  return slot_ >= 0 ? ekf_.landmark(slot_) : Eigen::Vector3d::Zero();
}

Eigen::Matrix3d ProposedModel::covariance_w() const {
  return slot_ >= 0 ? ekf_.landmark_covariance(slot_) : Eigen::Matrix3d::Zero();
}

BatchResult proposed_one_step_batch(slam_core::Ekf& ekf, const Pinhole& camera,
                                    const KnownPose& first, const KnownPose& second,
                                    const std::array<Eigen::Vector3d, kFig8Landmarks>& landmarks) {
  BatchResult result;
  const bool reset = ekf.reset(camera_pose_vector(first), slam_core::Matrix6d::Zero());
  std::array<slam_core::Observation, kFig8Landmarks> observations{};
  std::array<int, kFig8Landmarks> slot_of{};
  slot_of.fill(-1);
  int count = 0;
  for (std::size_t i = 0; i < kFig8Landmarks; ++i) {
    Eigen::Vector2d pixel;
    if (!reset || !observe(camera, first, landmarks[i], pixel)) {
      continue;
    }
    const int slot = ekf.initialize_landmark(pixel.x(), pixel.y());
    if (slot < 0 || !observe(camera, second, landmarks[i], pixel)) {
      continue;
    }
    slot_of[i] = slot;
    observations[static_cast<std::size_t>(count++)] =
        slam_core::Observation{slot, pixel.x(), pixel.y()};
  }
  if (reset && ekf.predict(translation_increment(first, second)).applied()) {
    result.fused = ekf.update(observations.data(), count).fused;
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < kFig8Landmarks; ++i) {
    if (slot_of[i] < 0) {
      result.estimate[i].setConstant(std::numeric_limits<double>::quiet_NaN());
      result.covariance[i].setConstant(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    result.estimate[i] = ekf.landmark(slot_of[i]);
    result.covariance[i] = ekf.landmark_covariance(slot_of[i]);
    sum += (result.estimate[i] - landmarks[i]).squaredNorm();
  }
  result.rms = count == static_cast<int>(kFig8Landmarks) && result.fused == count
                   ? std::sqrt(sum / static_cast<double>(kFig8Landmarks))
                   : std::numeric_limits<double>::quiet_NaN();
  return result;
}

NoisyRunResult proposed_noisy_run(slam_core::Ekf& ekf, const NoisyRunParams& params,
                                  const std::array<Eigen::Vector3d, kFig8Landmarks>& landmarks,
                                  std::uint32_t seed) {
  NoisyRunResult result;
  std::mt19937 generator(seed);
  std::normal_distribution<double> pixel_noise(0.0, params.pixel_noise_px);
  std::normal_distribution<double> yaw_noise(0.0, params.yaw_noise_rad);
  KnownPose truth;
  if (!ekf.reset(camera_pose_vector(truth), slam_core::Matrix6d::Zero())) {
    return result;
  }
  std::array<int, kFig8Landmarks> slots{};
  for (std::size_t i = 0; i < kFig8Landmarks; ++i) {
    Eigen::Vector2d pixel;
    if (!observe(params.camera, truth, landmarks[i], pixel)) {
      return result;
    }
    slots[i] = ekf.initialize_landmark(pixel.x() + pixel_noise(generator),
                                       pixel.y() + pixel_noise(generator));
    if (slots[i] < 0) {
      return result;
    }
  }
  for (int step = 0; step < params.steps; ++step) {
    const KnownPose next = moved_pose(truth, Motion::kForward, params.step);
    slam_core::OdometryIncrement u = translation_increment(truth, next);
    u.dpsi_c.z() = yaw_noise(generator);
    u.Q(5, 5) = params.yaw_noise_rad * params.yaw_noise_rad;
    if (!ekf.predict(u).applied()) {
      return result;
    }
    truth = next;
    std::array<slam_core::Observation, kFig8Landmarks> observations{};
    int count = 0;
    for (std::size_t i = 0; i < kFig8Landmarks; ++i) {
      Eigen::Vector2d pixel;
      if (!observe(params.camera, truth, landmarks[i], pixel)) {
        ++result.rejected;
        continue;
      }
      observations[static_cast<std::size_t>(count++)] = slam_core::Observation{
          slots[i], pixel.x() + pixel_noise(generator), pixel.y() + pixel_noise(generator)};
    }
    result.rejected += count - ekf.update(observations.data(), count).fused;
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < kFig8Landmarks; ++i) {
    sum += (ekf.landmark(slots[i]) - landmarks[i]).squaredNorm();
  }
  result.rms = std::sqrt(sum / static_cast<double>(kFig8Landmarks));
  result.completed = true;
  return result;
}

}  // namespace cleanslam::paper_models
