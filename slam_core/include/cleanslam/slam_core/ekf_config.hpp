#pragma once

#include "cleanslam/hal/capacities.hpp"

namespace cleanslam::slam_core {

// The members the parameter table lists are configuration keys (filter.*); the others keep these
// values in the firmware. The flags are the mechanisms measured on (docs/experiments.md, "Always
// on"): unit tests turn one off to compare it with the plain EKF it changes.
struct EkfConfig {
  // Eq. 14-15: std. dev. along the ray; the paper's range is 30 m .. 1000 m.
  double eps_ct_m = 30.0;
  // Eq. 13: depth assumed at a landmark's first sighting.
  double assumed_depth_m = 5.0;
  // Eq. 16: feature tracking and camera calibration errors, pixels.
  double eps_trk_px = 0.5;
  double eps_cal_px = 0.5;
  // Per-observation chi-square gate on the 3-D innovation (3 dof, 99%).
  double gate_chi2 = 11.34;
  // Per-observation chi-square gate on the pixel innovation (2 dof, 99%); 0 disables it. The
  // 3-D gate alone cannot reject an outlier of a landmark whose depth is still unknown: the
  // landmark's long axis and the measured ray span a plane of large variance that contains the
  // outlier's offset. In pixels that uncertainty is a segment of the epipolar line instead.
  double gate_pixel_chi2 = 9.21;
  // Landmark slots in use at most (the pool holds hal::kMaxLandmarks).
  int max_landmarks = hal::kMaxLandmarks;
  // A landmark is not initialized when its ray is within this angle of the last direction of
  // travel (no parallax will ever reach its depth); 0 disables the check.
  double min_ray_motion_angle_rad = 0.01;
  // Travel shorter than this gives no direction of travel for that check.
  double min_motion_for_direction_m = 0.005;
  // Landmarks closer than this along the ray are treated as behind the camera.
  double min_depth_m = 0.05;
  // Prediction is refused when |pitch| comes this close to +-pi/2 (eq. 4 is singular there).
  double max_abs_pitch_rad = 1.4;
  // Consider (Schmidt) update of young landmarks: while a landmark's depth relative to the
  // camera has a std. dev. above young_depth_std_fraction of that depth, its observations update
  // only the landmark itself (the gain rows of the pose and of the other landmarks are zero), so
  // the linearization error of its unknown depth (eq. 23's lever arm) cannot corrupt the pose.
  bool consider_young_landmarks = true;
  double young_depth_std_fraction = 0.3;
  // Depth bounds: an update that would move an observed landmark closer than min_depth_m or
  // farther than max_depth_m (0: no upper bound) along the optical axis drops that observation
  // (kDepthBound) and the rest is fused again.
  bool depth_bounds = true;
  double max_depth_m = 0.0;
  // Invariant-EKF reset after every state correction (update or merge): the covariance is carried
  // from the estimate the correction was linearized at to the corrected one, with the Jacobian of
  // a rotation about the vertical applied to every position (robot and landmarks). The global
  // rotation that no measurement can observe then stays unobserved, as in the invariant EKF of
  // Barrau and Bonnabel (2015); without it each correction claims a little of it (the EKF-SLAM
  // inconsistency of Huang et al.), and a heading that is lost still looks known.
  bool invariant_reset = true;
  // An update whose prior pose is too uncertain for the measurement's linearization (for some
  // sighting of an established landmark, the pose's share of the across-ray std. dev. sigma, as an
  // angle, makes the projection's second-order term f sigma^2 / 2 exceed the pixel noise) is
  // linearized at the planar pose that solves the frame's sightings of established landmarks with
  // the prior (solve_planar_pose): the iterated EKF's update from that pose.
  bool solve_pose_beyond_linear_range = true;
  // Merges (merge_landmarks) treat the kept entry as a considered state (Schmidt): the merge
  // corrects the robot and the rest of the map through their correlations with the two entries,
  // and neither moves the kept entry nor shrinks its covariance. Without it every merge pulls the
  // earlier map toward a remapped entry built from a drifted pose, and the map's claimed accuracy
  // compounds over the merges of a run.
  bool merge_considers_kept = true;
  // Smallest variance allowed on the diagonal of P after an update (the PSD guard).
  double min_variance = 1e-12;
};

}  // namespace cleanslam::slam_core
