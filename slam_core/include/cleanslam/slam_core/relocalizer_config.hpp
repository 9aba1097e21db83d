#pragma once

namespace cleanslam::slam_core {

struct RelocalizerConfig {
  // A corner is a candidate sighting of an earlier landmark when the landmark's first-sighting
  // patch, at one of a few scales, matches it with at least this NCC.
  float min_ncc = 0.85F;
  int candidates_per_landmark = 3;
  // A candidate's elevation above (or below) the camera gives its horizontal distance: at least
  // this tangent.
  double min_elevation_tan = 0.05;
  // Two candidates' horizontal distance apart, as seen and as mapped, agree to this much plus
  // this fraction of it.
  double pair_tolerance_m = 0.15;
  double pair_tolerance_fraction = 0.1;
  // A candidate is an inlier of a pose when its landmark projects this close to its corner.
  double inlier_px = 5.0;
  // A pose is taken with at least this many landmarks as inliers, and this many more than the
  // best pose whose inliers are mostly other landmarks (an ambiguous view) ...
  int min_inliers = 4;
  int min_margin = 1;
  // ... when the other landmarks it puts in view match their first-sighting patch (at the scale
  // their distance implies) within inlier_px of where they project more often than chance
  // explains: a patch matches near an unrelated place with probability chance_match, and the
  // count seen would come by chance with probability at most max_chance_probability.
  double chance_match = 0.1;
  double max_chance_probability = 0.001;
  // A pose that leaves no other landmark in view to check it needs this many inliers.
  int min_inliers_unchecked = 8;
  // Bounded work per step: landmarks matched, candidate rows of the pose search.
  int landmarks_per_step = 4;
  int rows_per_step = 2;
};

}  // namespace cleanslam::slam_core
