#include "cleanslam/firmware/slam_estimator.hpp"

#include <algorithm>
#include <cmath>

#include "cleanslam/firmware/program.hpp"
#include "cleanslam/slam_core/map_snapshot.hpp"

namespace cleanslam::firmware {

std::unique_ptr<Estimator> make_estimator(const FirmwareConfig& config) {
  return std::make_unique<SlamEstimator>(config);
}

SlamEstimator::SlamEstimator(const FirmwareConfig& config)
    : system_(std::make_unique<slam_core::SlamSystem>(config.calibration, slam_config(config))) {}

MapCounters SlamEstimator::map_counters() const {
  const slam_core::EkfCounters& c = ekf().counters();
  MapCounters m;
  m.initialized = c.landmarks_initialized;
  m.replaced = c.landmarks_replaced;
  m.deleted = c.landmarks_deleted;
  m.merged = c.landmarks_merged;
  m.merges_gated = c.merges_gated;
  return m;
}

ObservationRejections SlamEstimator::observation_rejections() const {
  static_assert(slam_core::kObservationResultCount <= kMaxRejectionReasons);
  const slam_core::RejectionCounters& c = ekf().counters().rejections;
  ObservationRejections out;
  for (int i = 0; i < slam_core::kObservationResultCount; ++i) {
    const auto r = static_cast<slam_core::ObservationResult>(i);
    if (r != slam_core::ObservationResult::kFused && c[r] > 0) {
      out.by_reason[static_cast<std::size_t>(out.count++)] = {slam_core::to_string(r), c[r]};
    }
  }
  return out;
}

bool SlamEstimator::wheel_yaw(WheelYawReport& out) const {
  const slam_core::SlamConfig& config = system_->config();
  if (!config.odometry.wheel_yaw.enabled) {
    return false;
  }
  const slam_core::WheelYawFusion& f = dead_reckoner().wheel_yaw_fusion();
  const Eigen::Vector3d& p = f.calibration();
  const Eigen::Matrix3d& P = f.calibration_covariance();
  out.gyro_bias_rad_s = p(0);
  out.scale = p(1);
  out.scale_std = std::sqrt(std::max(0.0, P(1, 1)));
  out.drift_rad_per_m = p(2);
  out.drift_std = std::sqrt(std::max(0.0, P(2, 2)));
  const slam_core::WheelYawCounters& k = f.counters();
  out.intervals_fused = k.intervals_fused;
  out.intervals_gated = k.intervals_gated;
  out.windows_used = k.windows_used;
  out.windows_gated = k.windows_gated;
  return true;
}

int SlamEstimator::landmarks(LandmarkEstimate* out, int max) const {
  const slam_core::Ekf& e = ekf();
  int n = 0;
  for (int s = 0; s < hal::kMaxLandmarks && n < max; ++s) {
    if (!e.slot_used(s)) {
      continue;
    }
    LandmarkEstimate& l = out[n++];
    l.slot = s;
    const Eigen::Vector3d p = e.landmark(s);
    const Eigen::Matrix3d c = e.landmark_covariance(s);
    l.position_m = {p.x(), p.y(), p.z()};
    for (Eigen::Index r = 0; r < 3; ++r) {
      for (Eigen::Index k = 0; k < 3; ++k) {
        l.covariance[static_cast<std::size_t>(3 * r + k)] = c(r, k);
      }
    }
  }
  return n;
}

bool SlamEstimator::map_snapshot(hal::TimeNs t_ns, hal::map_file::MapSnapshot& out) const {
  slam_core::snapshot_map(*system_, t_ns, out);
  return true;
}

}  // namespace cleanslam::firmware
