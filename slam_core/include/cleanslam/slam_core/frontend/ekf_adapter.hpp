#pragma once

#include <array>
#include <concepts>
#include <cstddef>
#include <span>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/slam_core/frontend/landmark_estimator.hpp"

namespace cleanslam::slam_core::frontend {

// Drives an EKF through the frame pipeline's LandmarkEstimator interface. Written against the
// EKF's API rather than its type, so that the front end builds without it:
//   bool predict_pixel(int slot, Prediction&) const   (Prediction: uv, S, depth_m, in_front)
//   int joint_pixel_innovation(std::span<const Observation>, std::span<double> nu,
//                              std::span<double> S) const
//   int initialize_landmark(double u_px, double v_px)
//   void delete_landmark(int slot)
//   const Status& update(const Observation*, int count)   (Status: int fused)
// and, when the estimator bounds its work per update call (optional: without them every update
// completes at once):
//   bool update_pending() const; bool continue_update(); const Status& last_update() const
// and, when the estimator has them (used for the patch scale, optional):
//   Vector6d camera_pose() const   (position first)
//   Eigen::Vector3d landmark(int slot) const   bool slot_used(int slot) const
// with Observation {int slot; double u_px; double v_px;}. For the project's EKF:
//   EkfAdapter<Ekf, Observation, PixelPrediction>.
template <class Estimator, class Observation, class Prediction>
class EkfAdapter final : public LandmarkEstimator {
 public:
  explicit EkfAdapter(Estimator& estimator) : estimator_(estimator) {}

  bool predict_pixel(int slot, PixelPrediction& out) override {
    Prediction p;
    if (!estimator_.predict_pixel(slot, p)) {
      return false;
    }
    out.uv = p.uv;
    out.S = p.S;
    out.depth_m = p.depth_m;
    out.in_front = p.in_front;
    return true;
  }

  int joint_pixel_innovation(std::span<const PixelObservation> obs, std::span<double> nu,
                             std::span<double> S) override {
    if (obs.size() > buffer_.size() || !convert(obs.data(), static_cast<int>(obs.size()))) {
      return -1;
    }
    return estimator_.joint_pixel_innovation(
        std::span<const Observation>(buffer_.data(), obs.size()), nu, S);
  }

  int initialize_landmark(double u_px, double v_px) override {
    return estimator_.initialize_landmark(u_px, v_px);
  }

  void delete_landmark(int slot) override { estimator_.delete_landmark(slot); }

  int update(const PixelObservation* obs, int count) override {
    if (!convert(obs, count)) {
      return 0;
    }
    return estimator_.update(buffer_.data(), count).fused;
  }
  bool camera_position(Eigen::Vector3d& out) override {
    if constexpr (requires(const Estimator& e) { e.camera_pose().template head<3>(); }) {
      out = estimator_.camera_pose().template head<3>();
      return out.allFinite();
    } else {
      return false;
    }
  }
  bool landmark_position(int slot, Eigen::Vector3d& out) override {
    if constexpr (requires(const Estimator& e) {
                    e.landmark(0);
                    e.slot_used(0);
                  }) {
      if (!estimator_.slot_used(slot)) {
        return false;
      }
      out = estimator_.landmark(slot);
      return out.allFinite();
    } else {
      return false;
    }
  }

  [[nodiscard]] bool update_pending() const override {
    if constexpr (kResumable) {
      return estimator_.update_pending();
    } else {
      return false;
    }
  }

  bool continue_update(int& fused) override {
    fused = 0;
    if constexpr (kResumable) {
      const bool done = estimator_.continue_update();
      fused = done ? estimator_.last_update().fused : 0;
      return done;
    } else {
      return true;
    }
  }

 private:
  static constexpr bool kResumable = requires(Estimator & e) {
    { e.update_pending() } -> std::convertible_to<bool>;
    { e.continue_update() } -> std::convertible_to<bool>;
    e.last_update().fused;
  };

  bool convert(const PixelObservation* obs, int count) {
    if (count < 0 || count > hal::kMaxObservationsPerFrame || (count > 0 && obs == nullptr)) {
      return false;
    }
    for (int i = 0; i < count; ++i) {
      Observation& o = buffer_[static_cast<std::size_t>(i)];
      o.slot = obs[i].slot;
      o.u_px = obs[i].u_px;
      o.v_px = obs[i].v_px;
    }
    return true;
  }

  Estimator& estimator_;
  std::array<Observation, hal::kMaxObservationsPerFrame> buffer_{};
};

}  // namespace cleanslam::slam_core::frontend
