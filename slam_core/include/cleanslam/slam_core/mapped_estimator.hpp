#pragma once

#include <span>

#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/frontend/ekf_adapter.hpp"
#include "cleanslam/slam_core/frontend/landmark_estimator.hpp"
#include "cleanslam/slam_core/map_manager.hpp"

namespace cleanslam::slam_core {

// The EKF as the frame pipeline's estimator, its landmarks made and deleted through the map's
// management (the tracker's slot is the track).
class MappedEstimator final : public frontend::LandmarkEstimator {
 public:
  MappedEstimator(Ekf& ekf, MapManager& map) : ekf_(ekf), map_(map) {}

  bool predict_pixel(int slot, frontend::PixelPrediction& out) override {
    return ekf_.predict_pixel(slot, out);
  }
  int joint_pixel_innovation(std::span<const frontend::PixelObservation> obs, std::span<double> nu,
                             std::span<double> S) override {
    return ekf_.joint_pixel_innovation(obs, nu, S);
  }
  int initialize_landmark(double u_px, double v_px) override {
    return map_.initialize(MapManager::kTrackerSlot, u_px, v_px, -1);
  }
  void delete_landmark(int slot) override {
    ekf_.delete_landmark(slot);
    map_.remove(slot);
  }
  int update(const frontend::PixelObservation* obs, int count) override {
    return ekf_.update(obs, count);
  }
  [[nodiscard]] bool update_pending() const override { return ekf_.update_pending(); }
  bool continue_update(int& fused) override { return ekf_.continue_update(fused); }
  bool camera_position(Eigen::Vector3d& out) override { return ekf_.camera_position(out); }
  bool landmark_position(int slot, Eigen::Vector3d& out) override {
    return ekf_.landmark_position(slot, out);
  }

 private:
  frontend::EkfAdapter<Ekf, Observation, PixelPrediction> ekf_;
  MapManager& map_;
};

}  // namespace cleanslam::slam_core
