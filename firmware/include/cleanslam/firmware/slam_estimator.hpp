#pragma once

#include <cstdint>
#include <memory>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/estimator.hpp"
#include "cleanslam/firmware/slam_config_from_firmware.hpp"
#include "cleanslam/slam_core/slam_system.hpp"

namespace cleanslam::firmware {

// The loop's estimator: slam_core::SlamSystem (dead reckoning, the EKF, the map's management and
// the front end for frames with track ids and for images) with the firmware's reports. The EKF's
// batch update is bounded per loop iteration: loop.frame_work_budget units of kUpdateWorkPerUnit.
class SlamEstimator final : public Estimator {
 public:
  static constexpr std::int64_t kUpdateWorkPerUnit = firmware::kUpdateWorkPerUnit;

  explicit SlamEstimator(const FirmwareConfig& config);

  void reset(hal::TimeNs /*t_ns*/) override { system_->reset(); }
  void set_down(hal::TimeNs t_ns) override { system_->set_down(t_ns); }
  [[nodiscard]] bool pose_lost() const override { return system_->pose_lost(); }
  void add_gyro(const hal::GyroSample& s) override { system_->add_gyro(s); }
  void add_encoder(const hal::EncoderSample& s) override { system_->add_encoder(s); }
  void predict(hal::TimeNs t_ns) override { system_->predict(t_ns); }
  void begin_frame(const hal::CameraFrame& frame) override { system_->begin_frame(frame); }
  bool step_frame(int& budget) override { return system_->step_frame(budget); }
  int update_records(const hal::log::UpdateRecord*& records) const override {
    return system_->update_records(records);
  }
  [[nodiscard]] hal::PoseEstimate pose(hal::TimeNs t_ns) const override {
    return system_->pose(t_ns);
  }
  [[nodiscard]] bool standing_still() const override { return system_->standing_still(); }
  [[nodiscard]] hal::PoseEstimate dead_reckoning_pose(hal::TimeNs t_ns) const override {
    return system_->dead_reckoning_pose(t_ns);
  }
  int landmarks(LandmarkEstimate* out, int max) const override;
  [[nodiscard]] MapCounters map_counters() const override;
  [[nodiscard]] ObservationRejections observation_rejections() const override;
  bool wheel_yaw(WheelYawReport& out) const override;
  bool map_snapshot(hal::TimeNs t_ns, hal::map_file::MapSnapshot& out) const override;

  [[nodiscard]] const slam_core::SlamSystem& system() const { return *system_; }
  [[nodiscard]] const slam_core::Ekf& ekf() const { return system_->ekf(); }
  [[nodiscard]] const slam_core::DeadReckoner& dead_reckoner() const {
    return system_->dead_reckoner();
  }
  [[nodiscard]] std::uint64_t image_frames() const { return system_->image_frames(); }

 private:
  std::unique_ptr<slam_core::SlamSystem> system_;  // allocated once, here
};

}  // namespace cleanslam::firmware
