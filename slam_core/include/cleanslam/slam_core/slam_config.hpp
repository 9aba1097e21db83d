#pragma once

#include <cstdint>

#include "cleanslam/slam_core/dead_reckoner.hpp"
#include "cleanslam/slam_core/ekf_config.hpp"
#include "cleanslam/slam_core/frontend/frame_pipeline.hpp"
#include "cleanslam/slam_core/relocalizer_config.hpp"

namespace cleanslam::slam_core {

// Map management shared by both input paths: which landmark a sighting belongs to, when a
// landmark is made, deleted, mapped again and merged.
struct MapConfig {
  // Re-sighting with the pose lost (yaw std. dev. above remap_min_yaw_std_deg): a landmark whose
  // predicted pixel std. dev. exceeds remap_pixel_std_px is mapped again from its ray and merged
  // into its earlier entry once its depth has converged or its track ends; 0: off.
  double remap_pixel_std_px = 30.0;
  double remap_min_yaw_std_deg = 3.0;
  // ... only in frames with at most this many mapped landmarks in view.
  int remap_max_mapped_in_view = 2;
  // Frames with track ids: no visual update with fewer inliers.
  int features_min_inliers = 1;
  // After a set-down (the wheel-drop switch released): a new map, or the map kept and the pose
  // relocalized against it, the carry being an unknown planar displacement with zero mean and
  // these std. devs. (x and y, yaw).
  enum class SetDown : std::uint8_t { kNewMap, kRelocalize };
  SetDown on_set_down = SetDown::kRelocalize;
  double relocalize_std_m = 0.3;
  double relocalize_std_yaw_deg = 20.0;
  // The pose is lost while the position's std. dev. (the larger of x and y) exceeds this.
  double pose_lost_position_std_m = 0.5;
};

// Everything the estimator is configured with. Each key is listed once, with its name, default,
// range, unit and meaning, in the parameter table, whose sections are these members' names
// (`map_management` for `map`).
struct SlamConfig {
  EkfConfig filter;
  DeadReckoningConfig odometry;
  frontend::FramePipelineConfig frontend;
  MapConfig map;
  // Image frames after a relocalizing set-down: the map found again by appearance and geometry.
  RelocalizerConfig relocalizer;
  // Work of one bounded part of the EKF's batch update (Ekf::set_update_step); 0: unbounded.
  std::int64_t update_work_step = 0;
};

}  // namespace cleanslam::slam_core
