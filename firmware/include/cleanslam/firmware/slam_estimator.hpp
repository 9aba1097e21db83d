#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/estimator.hpp"
#include "cleanslam/slam_core/dead_reckoner.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/frontend/ekf_adapter.hpp"
#include "cleanslam/slam_core/frontend/frame_pipeline.hpp"
#include "cleanslam/slam_core/frontend/jcbb.hpp"

namespace cleanslam::firmware {

// The paper's estimator on the loop: DeadReckoner -> Ekf.predict at every encoder sample and at
// each frame's time; frames with pixel observations and track ids (features.csv) go through the
// id -> landmark slot map: known ids are updated (JCBB over the joint pixel innovation, no update
// with fewer than frontend.min_inliers, Section 3.5), unseen ids are initialized undelayed
// (eq. 39-45). Nothing is fused while the robot stands still (Section 2.4). All storage is
// allocated by the constructor.
// Image frames without features go through the front end's resumable FramePipeline (Harris,
// search regions, LK tracking, JCBB, update, map management, initialization), one bounded step
// per loop iteration; it tracks but does not update while standing still.
// The EKF's batch update is bounded per loop iteration too: loop.frame_work_budget units of
// kUpdateWorkPerUnit (Ekf::set_update_step, about one host instruction each). It continues over
// the next iterations; prediction waits for it (the dead reckoner keeps accumulating) and no
// other update or initialization starts meanwhile.
class SlamEstimator final : public Estimator {
 public:
  static constexpr std::int64_t kUpdateWorkPerUnit = 32768;

  explicit SlamEstimator(const FirmwareConfig& config);

  void reset(hal::TimeNs t_ns) override;
  void set_down(hal::TimeNs t_ns) override;  // set_down.cpp
  [[nodiscard]] bool pose_lost() const override;
  void add_gyro(const hal::GyroSample& s) override;
  void add_encoder(const hal::EncoderSample& s) override;
  void predict(hal::TimeNs t_ns, bool gyro_ok) override;
  void begin_frame(const hal::CameraFrame& frame) override;
  bool step_frame(int& budget) override;
  int update_records(const hal::log::UpdateRecord*& records) const override;
  int take_fusion_records(const hal::log::FusionRecord*& records) override;
  [[nodiscard]] hal::PoseEstimate pose(hal::TimeNs t_ns) const override;
  [[nodiscard]] bool standing_still() const override;
  [[nodiscard]] hal::PoseEstimate dead_reckoning_pose(hal::TimeNs t_ns) const override;
  int landmarks(LandmarkEstimate* out, int max) const override;
  [[nodiscard]] MapCounters map_counters() const override;
  [[nodiscard]] ObservationRejections observation_rejections() const override;
  bool wheel_yaw(WheelYawReport& out) const override;

  [[nodiscard]] const slam_core::Ekf& ekf() const { return ekf_; }
  [[nodiscard]] const slam_core::DeadReckoner& dead_reckoner() const { return dr_; }
  [[nodiscard]] std::uint64_t image_frames() const { return image_frames_; }
  [[nodiscard]] const slam_core::frontend::FramePipeline& pipeline() const { return *pipeline_; }

 private:
  // The filter's gyro bias and wheel drift for the dead reckoner's weights
  // (filter.wheel_drift_state).
  void share_wheel_state();
  // The turns' difference's scalar updates as fusion records (take_fusion_records).
  void record_mismatch(hal::TimeNs t_ns);
  // Features path: association, JCBB and the update's start; false when nothing is fused
  // (standing still, everything recorded as skipped).
  bool associate_features();
  void record_features_update();
  void initialize_features();
  // The features path's relocalization (filter.remap_pixel_std_px): a re-sighted landmark whose
  // prediction is useless is mapped again; its earlier entry is merged in once the new one's
  // depth has converged or its track ended.
  [[nodiscard]] bool needs_remap(int slot) const;
  void merge_remapped();
  void collect_image_records();
  int slot_of(std::int64_t track_id) const;
  void record(const hal::FeatureObservation& f, hal::log::UpdateStatus status, int slot);

  FirmwareConfig config_;
  slam_core::DeadReckoner dr_;
  slam_core::Ekf ekf_;
  slam_core::frontend::Jcbb jcbb_;
  std::unique_ptr<slam_core::frontend::FramePipeline> pipeline_;  // allocated once, here
  slam_core::frontend::EkfAdapter<slam_core::Ekf, slam_core::Observation,
                                  slam_core::PixelPrediction>
      adapter_;
  bool image_mode_ = false;
  hal::TimeNs camera_offset_ns_ = 0;
  hal::TimeNs predicted_to_ns_ = -1;
  std::array<std::int64_t, hal::kMaxLandmarks> slot_owner_{};  // track id per slot, -1: free
  std::array<int, hal::kMaxLandmarks> merge_target_{};  // earlier entry of a remapped slot, -1
  bool remap_allowed_ = false;  // this frame: few enough mapped landmarks in view

  hal::CameraFrame frame_;
  bool frame_done_ = true;
  bool fusing_ = false;  // the features path's update is pending or just finished
  int obs_count_ = 0;
  int innovation_count_ = -1;
  int fresh_count_ = 0;
  bool updated_ = false;
  slam_core::frontend::JcbbResult jcbb_result_;
  std::array<hal::log::UpdateRecord, hal::kMaxFeaturesPerFrame> records_{};
  int record_count_ = 0;
  // The last prediction's turns' difference, one record per scalar update.
  std::array<hal::log::FusionRecord, 2> fusion_records_{};
  int fusion_record_count_ = 0;
  std::uint64_t image_frames_ = 0;
  bool relocalizing_ = false;              // set down with robot.on_set_down: relocalize
  std::uint64_t updates_at_set_down_ = 0;  // Ekf::counters().updates_applied then

  // Per-frame workspaces.
  static constexpr int kMaxObs = hal::kMaxObservationsPerFrame;
  std::array<slam_core::Observation, kMaxObs> obs_{};
  std::array<int, kMaxObs> obs_feature_{};
  std::array<slam_core::Observation, kMaxObs> inlier_obs_{};
  std::array<int, kMaxObs> inlier_feature_{};
  std::array<bool, kMaxObs> inlier_{};
  std::array<double, 2 * kMaxObs> nu_{};
  std::array<double, 4 * kMaxObs * kMaxObs> S_{};
  std::array<int, hal::kMaxFeaturesPerFrame> new_feature_{};
  std::array<int, hal::kMaxFeaturesPerFrame> feature_slot_{};  // per feature: its slot or -1
  std::array<int, hal::kMaxFeaturesPerFrame> remap_of_{};      // per new feature: its earlier slot
};

}  // namespace cleanslam::firmware
