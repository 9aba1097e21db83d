#include "cleanslam/slam_core/parameter_table.hpp"

#include <array>
#include <string_view>

#include "cleanslam/hal/capacities.hpp"

namespace cleanslam::slam_core {

namespace {

using hal::parameter_field;
using P = hal::Parameter<SlamConfig>;

// MapConfig::SetDown's values by name.
constexpr std::array<std::string_view, 2> kSetDownPolicies{"new_map", "relocalize"};

// Key, member, default, range (lo, hi, lo open), unit, meaning.
constexpr std::array kSlamParameters{
    P{"filter.eps_ct_m", [](SlamConfig& c) { return parameter_field(c.filter.eps_ct_m); }, 30.0,
      1.0, 1e4, false, "m",
      "std. dev. along the ray of a new landmark (eq. 14-15; paper: 30 .. 1000)"},
    P{"filter.assumed_depth_m",
      [](SlamConfig& c) { return parameter_field(c.filter.assumed_depth_m); }, 5.0, 0.1, 1e3, false,
      "m", "depth assumed at a landmark's first sighting (eq. 13)"},
    P{"filter.eps_trk_px", [](SlamConfig& c) { return parameter_field(c.filter.eps_trk_px); }, 0.5,
      0.0, 100.0, true, "px", "feature tracking error (eq. 16)"},
    P{"filter.eps_cal_px", [](SlamConfig& c) { return parameter_field(c.filter.eps_cal_px); }, 0.5,
      0.0, 100.0, false, "px", "camera calibration error (eq. 16)"},
    P{"filter.gate_chi2", [](SlamConfig& c) { return parameter_field(c.filter.gate_chi2); }, 11.34,
      0.0, 1e6, true, "", "per-observation gate on the 3-D innovation (chi-square, 3 dof, 99 %)"},
    P{"filter.max_landmarks", [](SlamConfig& c) { return parameter_field(c.filter.max_landmarks); },
      static_cast<double>(hal::kMaxLandmarks), 1, static_cast<double>(hal::kMaxLandmarks), false,
      "", "landmark slots in use at most"},
    P{"filter.young_depth_std_fraction",
      [](SlamConfig& c) { return parameter_field(c.filter.young_depth_std_fraction); }, 0.3, 0.0,
      10.0, true, "",
      "young (consider update) while a landmark's depth std. dev. / depth exceeds this"},
    P{"filter.max_depth_m", [](SlamConfig& c) { return parameter_field(c.filter.max_depth_m); },
      0.0, 0.0, 1e4, false, "m",
      "updates may not move a landmark beyond this depth (the workspace), 0: no bound"},
    P{"filter.gate_pixel_chi2",
      [](SlamConfig& c) { return parameter_field(c.filter.gate_pixel_chi2); }, 9.21, 0.0, 1e6,
      false, "", "per-observation gate on the pixel innovation (chi-square, 2 dof, 99 %), 0: off"},
    P{"filter.min_ray_motion_angle_rad",
      [](SlamConfig& c) { return parameter_field(c.filter.min_ray_motion_angle_rad); }, 0.01, 0.0,
      1.5, false, "rad",
      "no landmark is made on a ray this close to the direction of travel (no parallax), 0: off"},
    P{"filter.min_depth_m", [](SlamConfig& c) { return parameter_field(c.filter.min_depth_m); },
      0.05, 0.0, 10.0, true, "m",
      "landmarks closer than this along the ray count as behind the camera"},
    P{"odometry.encoder_yaw_noise_rad_per_sqrt_m",
      [](SlamConfig& c) { return parameter_field(c.odometry.encoder_yaw_noise_rad_per_sqrt_m); },
      0.03, 0.0, 10.0, true, "rad/sqrt(m)",
      "heading random walk from the encoders alone (gyro silent), per sqrt of the travel"},
    P{"odometry.gyro_bias_correlation_time_s",
      [](SlamConfig& c) { return parameter_field(c.odometry.gyro_bias_correlation_time_s); }, 10.0,
      0.0, 1e5, false, "s", "heading variance += gyro.bias_instability^2 * this * dt, 0: off"},
    P{"odometry.gyro_scale_error",
      [](SlamConfig& c) { return parameter_field(c.odometry.gyro_scale_error); }, 0.005, 0.0, 1.0,
      false, "", "relative gyro scale error: heading variance += (this * dyaw)^2, 0: off"},
    P{"odometry.wheel_yaw_window_intervals",
      [](SlamConfig& c) { return parameter_field(c.odometry.wheel_yaw.window_intervals); }, 40, 1,
      100000, false, "", "encoder intervals per update of the wheels' heading calibration"},
    P{"odometry.wheel_yaw_gate_chi2",
      [](SlamConfig& c) { return parameter_field(c.odometry.wheel_yaw.gate_chi2); }, 16.0, 0.0, 1e6,
      true, "",
      "a window or interval whose gyro-wheel mismatch exceeds this (chi-square, 1 dof) is not "
      "fused: a wheel slipped"},
    P{"odometry.wheel_yaw_scale_std",
      [](SlamConfig& c) { return parameter_field(c.odometry.wheel_yaw.scale_std); }, 0.2, 0.0, 10.0,
      false, "", "prior std. dev. of the wheels' heading scale error"},
    P{"odometry.wheel_yaw_drift_std_rad_per_m",
      [](SlamConfig& c) { return parameter_field(c.odometry.wheel_yaw.drift_std_rad_per_m); }, 0.5,
      0.0, 100.0, false, "rad/m",
      "prior std. dev. of the wheels' heading drift per metre (unequal wheel scales)"},
    P{"odometry.wheel_yaw_correlation_time_s",
      [](SlamConfig& c) {
        return parameter_field(c.odometry.wheel_yaw.calibration_correlation_time_s);
      },
      50.0, 0.0, 1e5, false, "s",
      "the heading variance counts that calibration's error as persisting this long"},
    P{"odometry.z_noise_m_per_sqrt_m",
      [](SlamConfig& c) { return parameter_field(c.odometry.z_noise_m_per_sqrt_m); }, 0.003, 0.0,
      10.0, false, "m/sqrt(m)",
      "height random walk the wheels cannot observe, per sqrt of the travel"},
    P{"odometry.roll_pitch_noise_rad_per_sqrt_m",
      [](SlamConfig& c) { return parameter_field(c.odometry.roll_pitch_noise_rad_per_sqrt_m); },
      0.003, 0.0, 10.0, false, "rad/sqrt(m)",
      "roll and pitch random walk the wheels cannot observe, per sqrt of the travel"},
    P{"odometry.outage_speed_time_constant_s",
      [](SlamConfig& c) { return parameter_field(c.odometry.outage_speed_time_constant_s); }, 10.0,
      0.0, 1e3, true, "s",
      "encoders silent: correlation time of the speed's error about the last wheel speed"},
    P{"odometry.outage_speed_std_m_s",
      [](SlamConfig& c) { return parameter_field(c.odometry.outage_speed_std_m_s); }, 0.1, 0.0,
      100.0, true, "m/s", "encoders silent: std. dev. of that error"},
    P{"odometry.standstill_rate_rad_s",
      [](SlamConfig& c) { return parameter_field(c.odometry.standstill_rate_rad_s); }, 0.02, 0.0,
      1.0, false, "rad/s",
      "standing still (no visual update, Section 2.4): no tick and |yaw rate - gyro bias| below "
      "this"},
    P{"map_management.remap_pixel_std_px",
      [](SlamConfig& c) { return parameter_field(c.map.remap_pixel_std_px); }, 30.0, 0.0, 1e4,
      false, "px",
      "predicted pixel std. dev. above which a re-sighted landmark is mapped again and merged, 0: "
      "off"},
    P{"map_management.remap_min_yaw_std_deg",
      [](SlamConfig& c) { return parameter_field(c.map.remap_min_yaw_std_deg); }, 3.0, 0.0, 180.0,
      false, "deg", "... only while the heading's std. dev. exceeds this (pose lost)"},
    P{"map_management.remap_max_mapped_in_view",
      [](SlamConfig& c) { return parameter_field(c.map.remap_max_mapped_in_view); }, 2, 0,
      static_cast<double>(hal::kMaxFeaturesPerFrame), false, "",
      "... and with at most this many mapped landmarks in the frame"},
    P{"map_management.pose_lost_position_std_m",
      [](SlamConfig& c) { return parameter_field(c.map.pose_lost_position_std_m); }, 0.5, 0.0, 1e3,
      true, "m", "the pose is lost while the position std. dev. (larger of x, y) exceeds this"},
    P{"map_management.features_min_inliers",
      [](SlamConfig& c) { return parameter_field(c.map.features_min_inliers); }, 1, 1,
      static_cast<double>(hal::kMaxObservationsPerFrame), false, "",
      "frames of tracked features (ids known): no visual update with fewer inliers"},
    P{"map_management.on_set_down",
      [](SlamConfig& c) { return hal::choice_field(c.map.on_set_down, kSetDownPolicies); }, 1.0,
      0.0, 0.0, false, "",
      "after a lift (source.lift_line): a new map, or relocalize keeping the map"},
    P{"map_management.relocalize_std_m",
      [](SlamConfig& c) { return parameter_field(c.map.relocalize_std_m); }, 0.3, 0.0, 100.0, false,
      "m", "relocalize: position uncertainty added at set-down"},
    P{"map_management.relocalize_std_yaw_deg",
      [](SlamConfig& c) { return parameter_field(c.map.relocalize_std_yaw_deg); }, 20.0, 0.0, 180.0,
      false, "deg", "relocalize: heading uncertainty added at set-down"},
    P{"frontend.min_inliers",
      [](SlamConfig& c) { return parameter_field(c.frontend.jcbb.min_inliers); }, 3, 1,
      static_cast<double>(hal::kMaxObservationsPerFrame), false, "",
      "no visual update with fewer jointly compatible observations (Section 3.5)"},
    P{"frontend.new_landmark_max_row_fraction",
      [](SlamConfig& c) { return parameter_field(c.frontend.new_landmark_max_row_fraction); }, 0.7,
      0.0, 1.0, true, "",
      "new landmarks only above this fraction of the image height, 1: the whole image"},
    P{"frontend.jcbb.confidence",
      [](SlamConfig& c) { return parameter_field(c.frontend.jcbb.confidence); }, 0.99, 0.0, 0.9999,
      true, "", "probability of data association's chi-square bounds (individual and joint)"},
    P{"frontend.harris.k", [](SlamConfig& c) { return parameter_field(c.frontend.harris.k); }, 0.04,
      0.0, 0.25, true, "", "Harris' k (Section 3.2)"},
    P{"frontend.harris.sigma_px",
      [](SlamConfig& c) { return parameter_field(c.frontend.harris.sigma_px); }, 1.0, 0.3, 1.5,
      false, "px", "std. dev. of the structure tensor's Gaussian weights"},
    P{"frontend.harris.min_distance_px",
      [](SlamConfig& c) { return parameter_field(c.frontend.harris.min_distance_px); }, 5.0, 0.0,
      100.0, false, "px", "corners at least this far apart (strongest first)"},
    P{"frontend.harris.max_corners",
      [](SlamConfig& c) { return parameter_field(c.frontend.harris.max_corners); },
      static_cast<double>(hal::kMaxCorners), 1, static_cast<double>(hal::kMaxCorners), false, "",
      "corners per frame at most"},
    P{"frontend.tracker.min_ncc",
      [](SlamConfig& c) { return parameter_field(c.frontend.tracker.min_ncc); }, 0.8, -1.0, 1.0,
      false, "", "a match's NCC clears this (Section 3.4)"},
    P{"frontend.search_region.gate_chi2",
      [](SlamConfig& c) { return parameter_field(c.frontend.region.gate_chi2); }, 9.21, 0.0, 1e6,
      true, "", "search region's chi-square bound (2 dof, 99 %)"},
    P{"frontend.search_region.max_half_extent_px",
      [](SlamConfig& c) { return parameter_field(c.frontend.region.max_half_extent_px); }, 40.0,
      0.0, 1000.0, true, "px", "the region reaches at most this far from the prediction"},
    P{"frontend.search_region.margin_px",
      [](SlamConfig& c) { return parameter_field(c.frontend.region.margin_px); }, 8, 8, 100, false,
      "px", "patch centres keep this far from the image border"},
    P{"frontend.landmark_book.max_consecutive_failures",
      [](SlamConfig& c) { return parameter_field(c.frontend.book.max_consecutive_failures); }, 3, 1,
      1000000, false, "frames", "a landmark in view failing this many frames in a row is deleted"},
    P{"frontend.landmark_book.min_matches_to_keep",
      [](SlamConfig& c) { return parameter_field(c.frontend.book.min_matches_to_keep); }, 3, 0,
      1000000, false, "", "a landmark matched fewer times is deleted at its first miss"},
    P{"frontend.landmark_book.min_in_view",
      [](SlamConfig& c) { return parameter_field(c.frontend.book.min_in_view); }, 5, 0,
      static_cast<double>(hal::kMaxLandmarks), false, "",
      "new landmarks are taken when fewer were matched ..."},
    P{"frontend.landmark_book.target_in_view",
      [](SlamConfig& c) { return parameter_field(c.frontend.book.target_in_view); }, 10, 0,
      static_cast<double>(hal::kMaxLandmarks), false, "",
      "... up to this many (Section 3.2: 5-10)"},
    P{"frontend.landmark_book.exclusion_px",
      [](SlamConfig& c) { return parameter_field(c.frontend.book.exclusion_px); }, 20.0, 0.0,
      1000.0, false, "px", "new landmarks keep this distance from every landmark in view"},
    P{"relocalizer.min_ncc", [](SlamConfig& c) { return parameter_field(c.relocalizer.min_ncc); },
      0.85, 0.0, 1.0, true, "",
      "after a set-down: a corner is a candidate sighting of a mapped landmark above this NCC"},
    P{"relocalizer.min_inliers",
      [](SlamConfig& c) { return parameter_field(c.relocalizer.min_inliers); }, 4, 2,
      static_cast<double>(hal::kMaxLandmarks), false, "",
      "a relocalized pose needs at least this many supporting landmarks"},
};

}  // namespace

std::span<const P> slam_parameters() {
  return kSlamParameters;
}

const P* find_slam_parameter(std::string_view key) {
  for (const P& p : kSlamParameters) {
    if (p.key == key) {
      return &p;
    }
  }
  return nullptr;
}

}  // namespace cleanslam::slam_core
