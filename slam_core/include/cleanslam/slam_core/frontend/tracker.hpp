#pragma once

#include <cstdint>

#include "cleanslam/hal/image.hpp"
#include "cleanslam/slam_core/frontend/harris.hpp"
#include "cleanslam/slam_core/frontend/patch.hpp"
#include "cleanslam/slam_core/frontend/search_region.hpp"

namespace cleanslam::slam_core::frontend {

struct TrackerConfig {
  // A match is accepted only when its NCC clears this (Section 3.4).
  float min_ncc = 0.8F;
  int max_iterations = 20;
  // Lucas-Kanade stops when the update is below this, in pixels.
  float convergence_px = 0.01F;
  // Harris corners inside the region tried as start points (those whose window is most similar
  // to the template first), besides the predicted pixel itself; a corner whose NCC is below
  // min_start_ncc is not tried.
  int max_corner_starts = 4;
  float min_start_ncc = 0.5F;
  // A start point may move at most this far before the run is abandoned.
  float max_travel_px = 10.0F;
  // Templates flatter than this standard deviation (gray levels) are not tracked.
  float min_template_std = 3.0F;
  // Templates less isotropic than this (PatchTemplate::isotropy) are edges, whose match slides
  // along the edge after the prediction: not tracked, and not taken as new landmarks.
  float min_template_isotropy = 0.03F;
  // Image windows flatter than this are not matched (black, white, saturated).
  float min_window_std = 1.0F;
  // Candidates whose NCC differ by less than this are ranked by distance to the prediction.
  float ncc_tie = 0.01F;
  // A match is refused as ambiguous (repetitive texture) when another candidate more than
  // distinct_px away matches within ambiguity_ncc of its NCC.
  float distinct_px = 3.0F;
  float ambiguity_ncc = 0.03F;
  float reacquire_min_ncc = 0.8F;
  float reacquire_box_px = 30.0F;
};

enum class TrackFailure : std::uint8_t {
  kNone,
  kNoRegion,
  kNoTemplate,
  kNoConvergence,
  kLowNcc,
  kAmbiguous,  // another place in the search box matches about as well (repetitive texture)
  kDuplicate,  // another landmark matched the same pixel with a higher NCC (frame pipeline)
};

struct TrackResult {
  bool found = false;
  TrackFailure failure = TrackFailure::kNone;
  double u_px = 0.0;
  double v_px = 0.0;
  float ncc = 0.0F;
  int starts_tried = 0;
  int iterations = 0;
};

// Outcome of one translation-only Lucas-Kanade run.
struct Refinement {
  bool converged = false;
  double u_px = 0.0;
  double v_px = 0.0;
  float ncc = 0.0F;
  int iterations = 0;
};

// Section 3.4: start points are the Harris corners inside the search region and the predicted
// pixel; from each, inverse-compositional Lucas-Kanade with a 2-DOF translation minimizes the
// zero-mean SSD between the image window and the scale-predicted template (the window's contrast
// matched to the template's, so that neither offset nor gain of the illumination moves the
// minimum); the candidate with the best NCC inside the gate is accepted when its NCC clears
// min_ncc.
class Tracker {
 public:
  explicit Tracker(const TrackerConfig& config = {}) : config_(config) {}

  // reacquire: the landmark has not been matched for a while (its prediction may be off by more
  // than its region says): the match must clear reacquire_min_ncc, and look-alikes are looked for
  // at least reacquire_box_px around the prediction.
  [[nodiscard]] TrackResult track(const hal::GrayImageView& image, const PatchTemplate& tmpl,
                                  const SearchRegion& region, const Corner* corners,
                                  int corner_count, bool reacquire = false) const;

  // One Lucas-Kanade run from (u, v).
  [[nodiscard]] Refinement refine(const hal::GrayImageView& image, const PatchTemplate& tmpl,
                                  double u_px, double v_px) const;

  [[nodiscard]] const TrackerConfig& config() const { return config_; }

 private:
  TrackerConfig config_;
};

}  // namespace cleanslam::slam_core::frontend
