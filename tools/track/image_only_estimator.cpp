#include "image_only_estimator.hpp"

#include <cstddef>

namespace cleanslam::tools::track {

namespace {
std::size_t idx(int slot) {
  return static_cast<std::size_t>(slot);
}
}  // namespace

bool ImageOnlyEstimator::used(int slot) const {
  return slot >= 0 && slot < hal::kMaxLandmarks && used_[idx(slot)];
}

bool ImageOnlyEstimator::predict_pixel(int slot, slam_core::frontend::PixelPrediction& out) {
  if (!used(slot)) {
    return false;
  }
  // A landmark born in this frame is where it was just seen.
  const double du = fresh_[idx(slot)] ? 0.0 : vel_u_;
  const double dv = fresh_[idx(slot)] ? 0.0 : vel_v_;
  out.uv = {u_[idx(slot)] + du, v_[idx(slot)] + dv};
  const double var = config_.sigma_common_px * config_.sigma_common_px +
                     config_.sigma_pixel_px * config_.sigma_pixel_px;
  out.S = Eigen::Matrix2d::Identity() * var;
  out.depth_m = 1.0;
  out.in_front = true;
  return true;
}

int ImageOnlyEstimator::joint_pixel_innovation(
    std::span<const slam_core::frontend::PixelObservation> obs, std::span<double> nu,
    std::span<double> S) {
  constexpr auto kMax = static_cast<std::size_t>(hal::kMaxObservationsPerFrame);
  if (obs.size() > kMax || nu.size() < 2 * obs.size() || S.size() < 4 * obs.size() * obs.size()) {
    return -1;
  }
  for (std::size_t i = 0; i < obs.size(); ++i) {
    if (!used(obs[i].slot)) {
      return -1;
    }
    slam_core::frontend::PixelPrediction p;
    predict_pixel(obs[i].slot, p);
    nu[2 * i] = obs[i].u_px - p.uv.x();
    nu[2 * i + 1] = obs[i].v_px - p.uv.y();
  }
  const auto count = static_cast<int>(obs.size());
  const int n = 2 * count;
  const double common = config_.sigma_common_px * config_.sigma_common_px;
  const double pixel = config_.sigma_pixel_px * config_.sigma_pixel_px;
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) {
      S[static_cast<std::size_t>(c * n + r)] =
          (r % 2 == c % 2 ? common : 0.0) + (r == c ? pixel : 0.0);
    }
  }
  return count;
}

int ImageOnlyEstimator::initialize_landmark(double u_px, double v_px) {
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    if (!used_[idx(s)]) {
      used_[idx(s)] = true;
      fresh_[idx(s)] = true;
      u_[idx(s)] = u_px;
      v_[idx(s)] = v_px;
      id_[idx(s)] = next_id_++;
      return s;
    }
  }
  return -1;
}

void ImageOnlyEstimator::delete_landmark(int slot) {
  if (used(slot)) {
    used_[idx(slot)] = false;
  }
}

// Positions are those of the last frame; the observations give this frame's motion.
int ImageOnlyEstimator::update(const slam_core::frontend::PixelObservation* obs, int count) {
  double du = 0.0;
  double dv = 0.0;
  int n = 0;
  for (int i = 0; i < count; ++i) {
    if (used(obs[i].slot) && !fresh_[idx(obs[i].slot)]) {
      du += obs[i].u_px - u_[idx(obs[i].slot)];
      dv += obs[i].v_px - v_[idx(obs[i].slot)];
      ++n;
    }
  }
  if (n == 0) {
    return 0;
  }
  du /= n;
  dv /= n;
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    if (used_[idx(s)] && !fresh_[idx(s)]) {
      u_[idx(s)] += du;
      v_[idx(s)] += dv;
    }
  }
  for (int i = 0; i < count; ++i) {
    if (used(obs[i].slot)) {
      u_[idx(obs[i].slot)] = obs[i].u_px;
      v_[idx(obs[i].slot)] = obs[i].v_px;
    }
  }
  vel_u_ = du;
  vel_v_ = dv;
  updated_ = true;
  return n;
}

void ImageOnlyEstimator::end_frame() {
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    // Without an update the landmarks coast with the last motion (new ones are where they were
    // just seen).
    if (used_[idx(s)] && !fresh_[idx(s)] && !updated_) {
      u_[idx(s)] += vel_u_;
      v_[idx(s)] += vel_v_;
    }
    fresh_[idx(s)] = false;
  }
  updated_ = false;
}

std::int64_t ImageOnlyEstimator::track_id(int slot) const {
  return used(slot) ? id_[idx(slot)] : -1;
}

}  // namespace cleanslam::tools::track
