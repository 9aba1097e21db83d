#include "cleanslam/firmware/slam_config_from_firmware.hpp"

namespace cleanslam::firmware {

slam_core::SlamConfig slam_config(const FirmwareConfig& c) {
  slam_core::SlamConfig s;
  slam_core::EkfConfig& e = s.filter;
  e.eps_ct_m = c.filter.eps_ct_m;
  e.assumed_depth_m = c.filter.assumed_depth_m;
  e.eps_trk_px = c.filter.eps_trk_px;
  e.eps_cal_px = c.filter.eps_cal_px;
  e.gate_chi2 = c.filter.gate_chi2;
  e.max_landmarks = c.filter.max_landmarks;
  e.consider_young_landmarks = c.filter.consider_young_landmarks;
  e.young_depth_std_fraction = c.filter.young_depth_std_fraction;
  e.young_depth_given_pose = c.filter.young_depth_given_pose;
  e.depth_bounds = c.filter.depth_bounds;
  e.invariant_reset = c.filter.invariant_reset;
  e.merge_considers_kept = c.filter.remap_merge_consider_earlier;
  e.second_order_yaw = c.filter.second_order_yaw;
  e.merge_across_ray = c.filter.remap_merge_across_ray;
  e.max_depth_m = c.filter.max_depth_m;
  e.gyro_bias_state = c.filter.gyro_bias_state;
  e.gyro_bias_walk = c.filter.gyro_bias_walk;
  e.distance_scale_state = c.filter.distance_scale_state;
  e.wheel_drift_state = c.filter.wheel_drift_state;
  e.wheel_drift_std_rad_per_m = c.filter.wheel_yaw_drift_std_rad_per_m;

  slam_core::DeadReckoningConfig& d = s.odometry;
  d.gyro_timeout_s = hal::to_seconds(c.loop.gyro_timeout_ns);
  d.encoder_yaw_noise_rad_per_sqrt_m = c.filter.encoder_yaw_noise_rad_per_sqrt_m;
  d.standstill_rate_rad_s = c.frontend.standstill_rate_rad_s;
  d.standstill_window_s = c.frontend.standstill_window_s;
  d.gyro_bias_correlation_time_s = c.filter.gyro_bias_correlation_time_s;
  d.distance_scale_correlation_m = c.filter.distance_scale_correlation_m;
  d.gyro_scale_error = c.filter.gyro_scale_error;
  d.bias_in_state = c.filter.gyro_bias_state;
  d.scale_in_state = c.filter.distance_scale_state;
  d.hold_heading_when_still = c.filter.hold_heading_when_still;
  d.wheel_yaw.enabled = c.filter.wheel_yaw_fusion;
  d.wheel_yaw.window_intervals = c.filter.wheel_yaw_window_intervals;
  d.wheel_yaw.gate_chi2 = c.filter.wheel_yaw_gate_chi2;
  d.wheel_yaw.scale_std = c.filter.wheel_yaw_scale_std;
  d.wheel_yaw.drift_std_rad_per_m = c.filter.wheel_yaw_drift_std_rad_per_m;
  d.wheel_yaw.calibration_correlation_time_s = c.filter.wheel_yaw_correlation_time_s;
  d.drift_in_state = c.filter.wheel_drift_state;

  s.frontend.jcbb.min_inliers = c.frontend.min_inliers;

  slam_core::MapConfig& m = s.map;
  m.reinit_behind_camera = c.filter.reinit_behind_camera;
  m.remap_pixel_std_px = c.filter.remap_pixel_std_px;
  m.remap_min_yaw_std_deg = c.filter.remap_min_yaw_std_deg;
  m.remap_max_mapped_in_view = c.filter.remap_max_mapped_in_view;
  m.remap_merge_gate_chi2 = c.filter.remap_merge_gate_chi2;
  m.features_min_inliers = c.frontend.features_min_inliers;
  m.on_set_down = c.robot.on_set_down == RobotSettings::SetDown::kRelocalize
                      ? slam_core::MapConfig::SetDown::kRelocalize
                      : slam_core::MapConfig::SetDown::kNewMap;
  m.relocalize_std_m = c.robot.relocalize_std_m;
  m.relocalize_std_yaw_deg = c.robot.relocalize_std_yaw_deg;

  s.gyro_errors_from_calibration = c.filter.gyro_errors_from_calibration;
  s.update_work_step = static_cast<std::int64_t>(c.loop.frame_work_budget) * kUpdateWorkPerUnit;
  return s;
}

}  // namespace cleanslam::firmware
