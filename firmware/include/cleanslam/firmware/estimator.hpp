#pragma once

#include <array>
#include <cstdint>

#include "cleanslam/hal/frame.hpp"
#include "cleanslam/hal/log_format.hpp"
#include "cleanslam/hal/map_file.hpp"
#include "cleanslam/hal/pose.hpp"
#include "cleanslam/hal/samples.hpp"

namespace cleanslam::firmware {

struct LandmarkEstimate {
  int slot = -1;
  std::array<double, 3> position_m{};
  std::array<double, 9> covariance{};  // row-major
};

// How the map changed over the run.
struct MapCounters {
  std::uint64_t initialized = 0;
  std::uint64_t replaced = 0;  // a full pool's least useful landmark, for a new one
  std::uint64_t deleted = 0;   // merged ones' second entries included
  std::uint64_t merged = 0;    // a remapped landmark joined to its earlier entry
  std::uint64_t merges_gated = 0;
};

// Measurements the filter did not fuse (camera observations, and turn differences that were not
// finite), by reason (slam_core::ObservationResult's names); reasons that never occurred are left
// out.
struct ObservationRejection {
  const char* reason = "";
  std::uint64_t count = 0;
};
inline constexpr int kMaxRejectionReasons = 16;
struct ObservationRejections {
  std::array<ObservationRejection, kMaxRejectionReasons> by_reason{};
  int count = 0;
};

// The wheel heading fusion's calibration at the end of a run (odometry.wheel_yaw_*).
struct WheelYawReport {
  double scale = 0.0;  // s: theta = (1 + s) w - c d
  double scale_std = 0.0;
  double drift_rad_per_m = 0.0;  // c
  double drift_std = 0.0;
  double gyro_bias_rad_s = 0.0;  // left after the dead reckoner's standstill estimate
  std::uint64_t intervals_fused = 0;
  std::uint64_t intervals_gated = 0;
  std::uint64_t windows_used = 0;
  std::uint64_t windows_gated = 0;
};

// What the loop drives: dead reckoning, the EKF and the frame pipeline. The loop validates the
// inputs first (finite, in order); an estimator sees only accepted samples.
class Estimator {
 public:
  virtual ~Estimator() = default;
  virtual void reset(hal::TimeNs t_ns) = 0;
  // Set down after a lift (the wheel-drop switch): by default a new map.
  virtual void set_down(hal::TimeNs t_ns) { reset(t_ns); }
  // The pose is not known (e.g. relocalizing after a set-down).
  [[nodiscard]] virtual bool pose_lost() const { return false; }
  virtual void add_gyro(const hal::GyroSample& s) = 0;
  virtual void add_encoder(const hal::EncoderSample& s) = 0;
  // Dead reckoning up to t_ns folded into the filter (prediction). The estimator judges a silent
  // gyro by the loop's own timeout (loop.gyro_timeout_s) and then heads by the encoders.
  virtual void predict(hal::TimeNs t_ns) = 0;
  // A frame to process; it stays valid until step_frame() reports it finished.
  virtual void begin_frame(const hal::CameraFrame& frame) = 0;
  // Runs pipeline steps while `budget` (work units) lasts; true when the frame is finished.
  virtual bool step_frame(int& budget) = 0;
  // Per-observation records of the last finished frame.
  virtual int update_records(const hal::log::UpdateRecord*& records) const = 0;
  [[nodiscard]] virtual hal::PoseEstimate pose(hal::TimeNs t_ns) const = 0;
  [[nodiscard]] virtual bool standing_still() const = 0;
  // Odometry alone (encoders and gyro), for comparison.
  [[nodiscard]] virtual hal::PoseEstimate dead_reckoning_pose(hal::TimeNs t_ns) const = 0;
  // The map: fills at most `max` landmarks, returns how many.
  virtual int landmarks(LandmarkEstimate* out, int max) const = 0;
  [[nodiscard]] virtual MapCounters map_counters() const { return {}; }
  [[nodiscard]] virtual ObservationRejections observation_rejections() const { return {}; }
  // False when the heading does not fuse the wheels.
  virtual bool wheel_yaw(WheelYawReport& /*out*/) const { return false; }
  // The map to keep for the next run (hal/map_file.hpp), saved at t_ns; false when the estimator
  // keeps no map. Changes nothing in the estimate.
  virtual bool map_snapshot(hal::TimeNs /*t_ns*/, hal::map_file::MapSnapshot& /*out*/) const {
    return false;
  }
};

}  // namespace cleanslam::firmware
