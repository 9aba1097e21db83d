#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/frame.hpp"
#include "cleanslam/hal/log_format.hpp"
#include "cleanslam/hal/pose.hpp"
#include "cleanslam/hal/samples.hpp"
#include "cleanslam/slam_core/dead_reckoner.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/frontend/frame_pipeline.hpp"
#include "cleanslam/slam_core/frontend/jcbb.hpp"
#include "cleanslam/slam_core/map_manager.hpp"
#include "cleanslam/slam_core/mapped_estimator.hpp"
#include "cleanslam/slam_core/relocalizer.hpp"
#include "cleanslam/slam_core/slam_config.hpp"

namespace cleanslam::slam_core {

// The paper's estimator behind one interface: DeadReckoner -> Ekf.predict at every prediction
// and at each frame's time, the map's management (MapManager) and the front end. Frames with
// pixel observations and track ids (features.csv) are associated by track id: known ids are
// updated (JCBB over the joint pixel innovation, no update with fewer than
// MapConfig::features_min_inliers, Section 3.5), unseen ids are initialized undelayed (eq. 39-45).
// Image frames go through the resumable FramePipeline (Harris, search regions, LK tracking, JCBB,
// update, initialization), one bounded step per step_frame() call. Nothing is fused while the
// robot stands still (Section 2.4). The EKF's batch update is bounded too
// (SlamConfig::update_work_step): it continues over the next step_frame() calls; prediction
// waits for it (the dead reckoner keeps accumulating). All storage is allocated by the
// constructor.
class SlamSystem {
 public:
  SlamSystem(const hal::Calibration& calibration, const SlamConfig& config);
  SlamSystem(const SlamSystem&) = delete;
  SlamSystem& operator=(const SlamSystem&) = delete;

  // A new map; the world frame is the body frame now.
  void reset();
  // Set down after a lift: a new map, or (MapConfig::on_set_down kRelocalize) the map kept and
  // the carry folded in as an unknown planar displacement (relocalize.cpp). After image frames
  // the map goes dormant until the Relocalizer finds it in a frame.
  void set_down(hal::TimeNs t_ns);
  // Relocalizing and no visual update since the set-down (image frames: the map not found again),
  // or the position's std. dev. beyond MapConfig::pose_lost_position_std_m (from the prediction
  // or update that passed it until one brings it below kPoseFoundStdFraction of it).
  [[nodiscard]] bool pose_lost() const;
  static constexpr double kPoseFoundStdFraction = 0.8;
  [[nodiscard]] bool position_std_exceeded() const { return position_std_exceeded_; }
  // The encoders are silent: the prediction's distance comes from the outage's motion model.
  [[nodiscard]] bool coasting() const { return dr_.coasting(); }

  void add_gyro(const hal::GyroSample& s) { dr_.add_gyro(s); }
  void add_encoder(const hal::EncoderSample& s) { dr_.add_encoder(s); }
  // Dead reckoning up to t_ns folded into the filter; deferred while an update is pending.
  void predict(hal::TimeNs t_ns);

  // A frame to process; it stays valid until step_frame() reports it finished.
  void begin_frame(const hal::CameraFrame& frame);
  // Bounded work on the frame (features: one unit per feature, then one update part per call;
  // images: one pipeline step per call, budget spent); true when the frame is finished.
  bool step_frame(int& budget);
  // The last finished frame's per-observation records.
  int update_records(const hal::log::UpdateRecord*& records) const {
    records = records_.data();
    return record_count_;
  }

  [[nodiscard]] hal::PoseEstimate pose(hal::TimeNs t_ns) const {
    return ekf_.body_pose_estimate(t_ns);
  }
  [[nodiscard]] hal::PoseEstimate dead_reckoning_pose(hal::TimeNs t_ns) const;
  [[nodiscard]] bool standing_still() const { return dr_.standing_still(); }

  [[nodiscard]] const Ekf& ekf() const { return ekf_; }
  [[nodiscard]] const DeadReckoner& dead_reckoner() const { return dr_; }
  [[nodiscard]] const MapManager& map() const { return map_; }
  [[nodiscard]] const frontend::FramePipeline& pipeline() const { return *pipeline_; }
  [[nodiscard]] std::uint64_t image_frames() const { return image_frames_; }
  // Image frames: times the pose was found again against a dormant map (relocalize.cpp).
  [[nodiscard]] std::uint64_t relocalizations() const { return relocalizations_; }
  [[nodiscard]] const SlamConfig& config() const { return config_; }

 private:
  void check_position_std();
  void record(const hal::FeatureObservation& f, hal::log::UpdateStatus status, int slot);
  // Features path (feature_frame.cpp).
  bool step_features(int& budget);
  bool associate_features();
  void record_features_update();
  void record_merges();
  void initialize_features();
  // Image path (image_frame.cpp).
  void collect_image_records();
  // Image path after a relocalizing set-down (relocalize.cpp): one bounded part of the search
  // for the dormant map in this frame; true when done.
  // The carry of a set-down (MapConfig::relocalize_std_m, relocalize_std_yaw_deg): the variances
  // of x, y and yaw.
  [[nodiscard]] Eigen::Vector3d set_down_variances() const;
  bool relocalize_step();
  void relocate(const Vector6d& camera_pose);

  hal::Calibration calibration_;
  SlamConfig config_;
  DeadReckoner dr_;
  Ekf ekf_;
  MapManager map_;
  frontend::Jcbb jcbb_;
  std::unique_ptr<frontend::FramePipeline> pipeline_;  // allocated once, here
  MappedEstimator mapped_;
  hal::TimeNs camera_offset_ns_ = 0;
  hal::TimeNs predicted_to_ns_ = -1;
  bool position_std_exceeded_ = false;

  hal::CameraFrame frame_;
  bool image_mode_ = false;
  bool frame_done_ = true;
  bool fusing_ = false;  // the features path's update is pending or just finished
  int obs_count_ = 0;
  int innovation_count_ = -1;
  int fresh_count_ = 0;
  bool updated_ = false;
  frontend::JcbbResult jcbb_result_;
  std::array<hal::log::UpdateRecord, hal::kMaxFeaturesPerFrame> records_{};
  int record_count_ = 0;
  std::uint64_t image_frames_ = 0;
  bool relocalizing_ = false;
  std::uint64_t updates_at_set_down_ = 0;
  Relocalizer relocalizer_;
  bool relocalizer_started_ = false;
  int relocalizer_cursor_ = 0;
  std::uint64_t relocalizations_ = 0;

  // Per-frame workspaces of the features path.
  static constexpr int kMaxObs = hal::kMaxObservationsPerFrame;
  std::array<Observation, kMaxObs> obs_{};
  std::array<int, kMaxObs> obs_feature_{};
  std::array<Observation, kMaxObs> inlier_obs_{};
  std::array<bool, kMaxObs> inlier_{};
  std::array<double, std::size_t{2} * kMaxObs> nu_{};
  std::array<double, std::size_t{4} * kMaxObs * kMaxObs> S_{};
  std::array<int, hal::kMaxFeaturesPerFrame> new_feature_{};
  std::array<int, hal::kMaxFeaturesPerFrame> feature_slot_{};
  std::array<int, hal::kMaxFeaturesPerFrame> remap_of_{};
};

}  // namespace cleanslam::slam_core
