#pragma once

#include <string>
#include <vector>

#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/firmware/recorder.hpp"
#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/readers/result.hpp"

namespace cleanslam::firmware {

// The EKF's parameters (slam_core::EkfConfig) and the initial pose uncertainty.
struct FilterSettings {
  double eps_ct_m = 30.0;        // eq. 14-15, along the ray (paper: 30 m .. 1000 m)
  double assumed_depth_m = 5.0;  // eq. 13
  double eps_trk_px = 0.5;       // eq. 16
  double eps_cal_px = 0.5;       // eq. 16
  double gate_chi2 = 11.34;      // per observation, 3 dof, 99 %
  int max_landmarks = 128;       // slots in use at most (<= hal::kMaxLandmarks)
  // Heading from the encoders alone while the gyro is silent: random walk per sqrt(metre).
  double encoder_yaw_noise_rad_per_sqrt_m = 0.03;
  // Consider (Schmidt) update while a landmark's relative depth std. dev. exceeds the fraction.
  bool consider_young_landmarks = true;
  double young_depth_std_fraction = 0.3;
  bool young_depth_given_pose = false;  // judged on the depth's std. dev. given the pose
  // Depth bounds of updates along the optical axis: in front of the camera, and within
  // max_depth_m (the workspace's size, 0: no upper bound).
  bool depth_bounds = true;
  double max_depth_m = 0.0;
  // Prediction noise of persistent odometry errors (slam_core::DeadReckoningConfig), 0: off.
  double gyro_bias_correlation_time_s = 10.0;
  double distance_scale_correlation_m = 0.0;
  double gyro_scale_error = 0.005;
  // Residual gyro bias as a filter state (slam_core::EkfConfig::gyro_bias_state).
  bool gyro_bias_state = false;
  double gyro_bias_walk = 0.0;  // rad/s/sqrt(s)
  // The wheels' distance scale error as a filter state
  // (slam_core::EkfConfig::distance_scale_state).
  bool distance_scale_state = false;
  // gyro_scale_error and gyro_bias_walk at least the calibration's gyro.scale_error, bias_walk.
  bool gyro_errors_from_calibration = false;
  // Heading held while the wheels stand still (slam_core::DeadReckoningConfig).
  bool hold_heading_when_still = true;
  // Heading from the gyro and the wheels together, the wheels' heading scale and drift per metre
  // learnt against the gyro (slam_core::WheelYawFusionConfig).
  bool wheel_yaw_fusion = true;
  int wheel_yaw_window_intervals = 40;
  double wheel_yaw_gate_chi2 = 16.0;
  double wheel_yaw_scale_std = 0.2;
  double wheel_yaw_drift_std_rad_per_m = 0.5;
  double wheel_yaw_correlation_time_s = 50.0;
  // The wheels' drift per metre as a filter state beside the gyro bias state, learnt from the
  // gyro's and the wheels' turns and from the camera (slam_core::EkfConfig::wheel_drift_state);
  // needs wheel_yaw_fusion and gyro_bias_state.
  bool wheel_drift_state = false;
  // A tracked feature whose landmark is predicted behind the camera re-initializes the landmark.
  bool reinit_behind_camera = false;
  // Re-sighting with the pose lost (yaw std. dev. above remap_min_yaw_std_deg): a tracked landmark
  // whose predicted pixel std. dev. exceeds remap_pixel_std_px (or that is predicted behind the
  // camera) is mapped again from its ray and merged into its earlier entry
  // (slam_core::Ekf::merge_landmarks) once its depth has converged or its track ends; 0: off.
  double remap_pixel_std_px = 30.0;
  double remap_min_yaw_std_deg = 3.0;
  // ... and only in frames with at most this many mapped landmarks in view: three bearings or
  // more fix the whole pose at once, and the batch update (JCBB-checked) relocalizes directly.
  int remap_max_mapped_in_view = 2;
  // The merge's chi-square gate (3 dof); 0: none (track ids make the two entries the same point).
  double remap_merge_gate_chi2 = 0.0;
  // The merge corrects the robot toward the earlier entry and leaves the entry and its covariance
  // as they were (slam_core::EkfConfig::merge_considers_kept).
  bool remap_merge_consider_earlier = true;
  // Second-order yaw terms in the camera measurement's covariance
  // (slam_core::EkfConfig::second_order_yaw).
  bool second_order_yaw = false;
  // Merges constrain only across the camera's ray to the remapped entry
  // (slam_core::EkfConfig::merge_across_ray).
  bool remap_merge_across_ray = false;
  // The invariant EKF's covariance reset after each correction (slam_core::EkfConfig).
  bool invariant_reset = true;
};

struct FrontendSettings {
  int min_inliers = 3;  // no visual update with fewer (Section 3.3)
  // The same for frames with tracked features (ids known, no data association to confirm).
  int features_min_inliers = 1;
  // Standing still (no visual update, Section 2.4): no tick and |yaw rate - bias| below this
  // for standstill_window_s.
  double standstill_rate_rad_s = 0.02;
  double standstill_window_s = 0.5;
};

struct SourceSettings {
  enum class Kind { kDrivers, kDataset, kLog };
  Kind kind = Kind::kDrivers;
  std::string path;       // dataset folder or log file
  bool realtime = false;  // pace a dataset or log in real time instead of as fast as possible
  std::string camera_device = "/dev/video0";
  std::string can_interface = "can0";
  std::string gpio_chip = "/dev/gpiochip0";
  int lift_line = -1;  // GPIO line of the wheel-drop switch; -1: none
};

struct SinkSettings {
  std::string tum_path;                // TUM trajectory file; empty: none
  std::string diagnostics_path;        // per-update records (CSV); empty: none
  std::string fusion_path;             // odometry fusions' records (CSV); empty: none
  bool can = false;                    // CAN pose frame through the driver
  std::string can_interface = "can0";  // pose frames 0x201/0x202 of docs/can.md
};

// The robot's GPIO wiring (lines of source.gpio_chip) and what the wheel-drop switch means.
struct RobotSettings {
  // Set down after a lift: relocalize against the existing map (an unknown displacement of
  // relocalize_std_m, relocalize_std_yaw_deg folded into the pose covariance; the pose stays
  // lost until a visual update fuses), or start a new map at the set-down pose.
  enum class SetDown { kRelocalize, kNewMap };
  SetDown on_set_down = SetDown::kNewMap;
  double relocalize_std_m = 0.3;
  double relocalize_std_yaw_deg = 20.0;
  int status_led_line = -1;  // GPIO output: steady OK, slow blink degraded, fast blink fault
  int gyro_ready_line = -1;  // GPIO input, rising edge when the gyro sampled; -1: CAN time
  double gyro_ready_max_latency_s = 0.008;  // edge to CAN reception, at most
};

struct FirmwareConfig {
  hal::Calibration calibration;
  bool calibration_from_dataset = true;  // a dataset source brings its own sensors.yaml
  FilterSettings filter;
  FrontendSettings frontend;
  LoopOptions loop;
  SourceSettings source;
  SinkSettings sinks;
  RecorderOptions recorder;
  RobotSettings robot;
};

struct ConfigResult {
  FirmwareConfig config;
  std::vector<std::string> warnings;
  std::vector<std::string> errors;  // each names the file, line and key
  [[nodiscard]] bool ok() const { return errors.empty(); }
};

// Reads `path` (empty: all defaults), applies "key.sub=value" overrides, validates every key.
ConfigResult load_config(const std::string& path, const std::vector<std::string>& overrides);
// The same from a text (a recorded configuration).
ConfigResult parse_config(const std::string& text, const std::string& file_name,
                          const std::vector<std::string>& overrides);
// Every key with its value, in a form parse_config() reads back to the same configuration.
std::string config_text(const FirmwareConfig& config);

}  // namespace cleanslam::firmware
