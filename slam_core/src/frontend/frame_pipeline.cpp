#include "cleanslam/slam_core/frontend/frame_pipeline.hpp"

#include <algorithm>
#include <span>

namespace cleanslam::slam_core::frontend {

namespace {
template <typename T, std::size_t N>
T& at(std::array<T, N>& a, int i) {
  return a[static_cast<std::size_t>(i)];
}
}  // namespace

FramePipeline::FramePipeline(const FramePipelineConfig& config)
    : config_(config),
      detector_(config.harris),
      tracker_(config.tracker),
      jcbb_(config.jcbb),
      book_(config.book) {
  config_.detect_rows_per_step = std::max(1, config_.detect_rows_per_step);
  config_.predictions_per_step = std::max(1, config_.predictions_per_step);
  config_.tracks_per_step = std::max(1, config_.tracks_per_step);
  config_.initializations_per_step = std::max(1, config_.initializations_per_step);
}

void FramePipeline::forget_map() {
  for (int slot = 0; slot < hal::kMaxLandmarks; ++slot) {
    book_.remove(slot);
    patches_.clear(slot);
  }
  stage_ = FrameStage::kIdle;
  report_ = FrameReport{};
  track_count_ = 0;
  occupied_count_ = 0;
  obs_count_ = 0;
  new_corner_count_ = 0;
  new_count_ = 0;
  cursor_ = 0;
}

void FramePipeline::suspend_map() {
  for (int slot = 0; slot < hal::kMaxLandmarks; ++slot) {
    book_.remove(slot);
  }
}

void FramePipeline::resume(int slot) {
  if (patches_.get(slot) != nullptr) {
    book_.resume(slot);
  }
}

void FramePipeline::forget(int slot) {
  book_.remove(slot);
  patches_.clear(slot);
}

ImageCheck FramePipeline::begin_frame(const hal::GrayImageView& image, bool allow_update) {
  report_ = FrameReport{};
  image_ = image;
  allow_update_ = allow_update;
  track_count_ = 0;
  occupied_count_ = 0;
  obs_count_ = 0;
  new_corner_count_ = 0;
  new_count_ = 0;
  cursor_ = 0;
  report_.image_check = check_image(image, config_.width, config_.height);
  stage_ = report_.image_check == ImageCheck::kOk ? FrameStage::kDetect : FrameStage::kDone;
  // Also abandons a detection left unfinished by a previous frame.
  detector_.begin(image, config_.width, config_.height);
  return report_.image_check;
}

const char* FramePipeline::describe(char* out, std::size_t out_size) const {
  return describe_image_check(report_.image_check, image_, config_.width, config_.height, out,
                              out_size);
}

bool FramePipeline::step(LandmarkEstimator& estimator) {
  if (stage_ == FrameStage::kIdle || stage_ == FrameStage::kDone) {
    return false;
  }
  ++report_.steps;
  switch (stage_) {
    case FrameStage::kDetect:
      do_detect();
      break;
    case FrameStage::kPredict:
      do_predict(estimator);
      break;
    case FrameStage::kTrack:
      do_track();
      break;
    case FrameStage::kAssociate:
      do_associate(estimator);
      break;
    case FrameStage::kUpdate:
      do_update(estimator);
      break;
    case FrameStage::kFuse:
      do_fuse(estimator);
      break;
    case FrameStage::kManage:
      do_manage(estimator);
      break;
    case FrameStage::kInitialize:
      do_initialize(estimator);
      break;
    case FrameStage::kIdle:
    case FrameStage::kDone:
      break;
  }
  return stage_ != FrameStage::kDone;
}

const FrameReport& FramePipeline::finish(LandmarkEstimator& estimator) {
  while (step(estimator)) {
  }
  return report_;
}

void FramePipeline::do_detect() {
  if (!detector_.step(config_.detect_rows_per_step)) {
    return;
  }
  report_.corners = detector_.corner_count();
  report_.featureless = report_.corners == 0;
  cursor_ = 0;
  // A frame without a single corner (black, white, saturated, textureless) is not evidence
  // against any landmark: nothing is searched, counted or initialized.
  stage_ = report_.featureless ? FrameStage::kDone : FrameStage::kPredict;
}

void FramePipeline::do_predict(LandmarkEstimator& est) {
  if (cursor_ == 0) {
    camera_known_ = est.camera_position(camera_);
  }
  int done = 0;
  while (cursor_ < hal::kMaxLandmarks && done < config_.predictions_per_step) {
    const int slot = cursor_++;
    if (!book_.active(slot)) {
      continue;
    }
    ++done;
    PixelPrediction pred;
    if (!est.predict_pixel(slot, pred)) {
      continue;
    }
    ++report_.predicted;
    const SearchRegion region =
        make_search_region(pred, config_.width, config_.height, config_.region);
    if (!region.valid) {
      continue;
    }
    const bool inside = region.in_box(pred.uv.x(), pred.uv.y());
    report_.in_view += inside ? 1 : 0;
    Eigen::Vector3d landmark;
    const bool has_distance = camera_known_ && est.landmark_position(slot, landmark);
    // Seen too differently from the first sighting: still searched, but a miss is not held
    // against it.
    const bool expected = !has_distance || matchable(slot, landmark);
    report_.unmatchable += expected ? 0 : 1;
    // When there are more candidates than tracks: young landmarks in view first (a miss deletes
    // them), then those in view as first seen, then the rest.
    const int priority = !inside ? 0 : book_.young(slot) ? 3 : expected ? 2 : 1;
    int index = track_count_;
    if (track_count_ < kMaxTracks) {
      ++track_count_;
      ++report_.searched;
    } else {
      index = 0;
      for (int i = 1; i < kMaxTracks; ++i) {
        if (at(tracks_, i).priority < at(tracks_, index).priority) {
          index = i;
        }
      }
      const bool replace = at(tracks_, index).priority < priority;
      const Eigen::Vector2d& spare = replace ? at(tracks_, index).region.center : pred.uv;
      at(occupied_u_, occupied_count_) = spare.x();
      at(occupied_v_, occupied_count_) = spare.y();
      ++occupied_count_;
      if (!replace) {
        continue;
      }
    }
    TrackRecord& t = at(tracks_, index);
    t = TrackRecord{};
    t.slot = slot;
    t.region = region;
    t.predicted_depth_m = pred.depth_m;
    t.center_inside = inside && expected;
    t.priority = priority;
    t.has_distance = has_distance;
    t.landmark = landmark;
    t.distance_m = has_distance ? (landmark - camera_).norm() : 0.0;
  }
  if (cursor_ >= hal::kMaxLandmarks) {
    cursor_ = 0;
    stage_ = FrameStage::kTrack;
  }
}

bool FramePipeline::matchable(int slot, const Eigen::Vector3d& landmark) const {
  const LandmarkPatch* patch = patches_.get(slot);
  if (patch == nullptr || !patch->has_anchor) {
    return true;
  }
  const Eigen::Vector3d from_anchor =
      landmark - Eigen::Vector3d(patch->anchor[0], patch->anchor[1], patch->anchor[2]);
  const Eigen::Vector3d from_camera = landmark - camera_;
  const double a = from_anchor.norm();
  const double c = from_camera.norm();
  if (!(a > 0.0) || !(c > 0.0)) {
    return true;
  }
  const double scale = a / c;
  const double max_scale = config_.max_view_scale;
  return scale <= max_scale && scale * max_scale >= 1.0 &&
         from_anchor.dot(from_camera) >= config_.min_view_cos * a * c;
}

double FramePipeline::patch_scale(const LandmarkPatch& patch, const TrackRecord& t) const {
  if (patch.has_anchor && t.has_distance) {
    const Eigen::Vector3d anchor(patch.anchor[0], patch.anchor[1], patch.anchor[2]);
    return predicted_patch_scale((t.landmark - anchor).norm(), t.distance_m);
  }
  return predicted_patch_scale(patch.first_depth_m, t.predicted_depth_m);
}

void FramePipeline::do_track() {
  const int end = std::min(track_count_, cursor_ + config_.tracks_per_step);
  for (; cursor_ < end; ++cursor_) {
    TrackRecord& t = at(tracks_, cursor_);
    const LandmarkPatch* patch = patches_.get(t.slot);
    PatchTemplate tmpl;
    if (patch == nullptr ||
        !make_template(*patch, patch_scale(*patch, t), config_.tracker.min_template_std, tmpl)) {
      t.result.failure = TrackFailure::kNoTemplate;
      continue;
    }
    const bool reacquire = book_.frames_since_match(t.slot) > config_.reacquire_after_frames;
    t.result = tracker_.track(image_, tmpl, t.region, detector_.corners(), detector_.corner_count(),
                              reacquire);
    if (t.result.found) {
      ++report_.tracked;
      at(obs_, obs_count_) = {t.slot, t.result.u_px, t.result.v_px};
      at(obs_track_, obs_count_) = cursor_;
      ++obs_count_;
    }
  }
  if (cursor_ >= track_count_) {
    cursor_ = 0;
    stage_ = FrameStage::kAssociate;
  }
}

void FramePipeline::do_associate(LandmarkEstimator& est) {
  stage_ = FrameStage::kUpdate;
  // Two landmarks on one pixel: only the better match stays.
  const double dup2 = config_.duplicate_px * config_.duplicate_px;
  int kept = 0;
  for (int i = 0; i < obs_count_; ++i) {
    TrackRecord& ti = at(tracks_, at(obs_track_, i));
    bool drop = false;
    for (int j = 0; j < obs_count_ && !drop; ++j) {
      if (j == i) {
        continue;
      }
      const TrackRecord& tj = at(tracks_, at(obs_track_, j));
      const double du = ti.result.u_px - tj.result.u_px;
      const double dv = ti.result.v_px - tj.result.v_px;
      drop = du * du + dv * dv < dup2 &&
             (tj.result.ncc > ti.result.ncc || (tj.result.ncc == ti.result.ncc && j < i));
    }
    if (drop) {
      ti.result.found = false;
      ti.result.failure = TrackFailure::kDuplicate;
      ++report_.duplicates;
      --report_.tracked;
      continue;
    }
    at(obs_, kept) = at(obs_, i);
    at(obs_track_, kept) = at(obs_track_, i);
    ++kept;
  }
  obs_count_ = kept;
  if (obs_count_ == 0) {
    return;
  }
  const int m = est.joint_pixel_innovation(
      std::span<const PixelObservation>(obs_.data(), static_cast<std::size_t>(obs_count_)), nu_,
      S_);
  if (m != obs_count_) {
    report_.innovation_rejected = true;
    return;
  }
  report_.jcbb = jcbb_.solve(nu_.data(), S_.data(), m, inlier_.data());
  report_.inliers = report_.jcbb.inlier_count;
  report_.outliers = m - report_.jcbb.inlier_count;
  for (int i = 0; i < m; ++i) {
    at(tracks_, at(obs_track_, i)).inlier = at(inlier_, i);
  }
}

void FramePipeline::do_update(LandmarkEstimator& est) {
  stage_ = FrameStage::kManage;
  if (!report_.jcbb.update || !allow_update_) {
    return;
  }
  // The inliers, in order, at the front of obs_.
  int n = 0;
  for (int i = 0; i < obs_count_; ++i) {
    if (at(inlier_, i)) {
      at(obs_, n++) = at(obs_, i);
    }
  }
  report_.fused = est.update(obs_.data(), n);
  report_.updated = report_.fused > 0;
  if (est.update_pending()) {
    stage_ = FrameStage::kFuse;
  }
}

void FramePipeline::do_fuse(LandmarkEstimator& est) {
  int fused = 0;
  if (!est.continue_update(fused)) {
    return;
  }
  report_.fused = fused;
  report_.updated = fused > 0;
  stage_ = FrameStage::kManage;
}

void FramePipeline::do_manage(LandmarkEstimator& est) {
  book_.next_frame();
  matched_now_.fill(false);
  for (int i = 0; i < track_count_; ++i) {
    const TrackRecord& t = at(tracks_, i);
    const bool matched = t.result.found && t.inlier;
    at(matched_now_, t.slot) = matched;
    if ((matched || t.center_inside) && book_.record(t.slot, matched)) {
      remove_landmark(est, t.slot);
    }
  }
  for (int slot = 0; slot < hal::kMaxLandmarks; ++slot) {
    if (book_.active(slot) && book_.young(slot) && !at(matched_now_, slot)) {
      remove_landmark(est, slot);
    }
  }
  // Landmarks matched in this frame (inliers) count as in view; new ones are wanted when there
  // are fewer than min_in_view, up to target_in_view, away from every landmark in view.
  int matched = 0;
  for (int i = 0; i < track_count_; ++i) {
    const TrackRecord& t = at(tracks_, i);
    if (book_.active(t.slot)) {
      at(occupied_u_, occupied_count_) = t.result.found ? t.result.u_px : t.region.center.x();
      at(occupied_v_, occupied_count_) = t.result.found ? t.result.v_px : t.region.center.y();
      ++occupied_count_;
      matched += (t.result.found && t.inlier) ? 1 : 0;
    }
  }
  new_corner_count_ = 0;
  new_wanted_ = 0;
  const LandmarkBookConfig& bc = book_.config();
  if (matched < bc.min_in_view) {
    new_wanted_ = std::min(bc.target_in_view - matched, hal::kMaxCorners);
    // Twice as many candidates: those whose patch is an edge are passed over.
    new_corner_count_ = select_new_corners(
        detector_.corners(), detector_.corner_count(), occupied_u_.data(), occupied_v_.data(),
        occupied_count_, bc.exclusion_px, config_.width, new_landmark_rows(),
        kStoredPatchRadius + 2, std::min(2 * new_wanted_, hal::kMaxCorners), new_corners_.data());
  }
  cursor_ = 0;
  stage_ = new_corner_count_ > 0 ? FrameStage::kInitialize : FrameStage::kDone;
}

int FramePipeline::new_landmark_rows() const {
  // select_new_corners keeps corners at most rows - 1 - margin.
  const double last = config_.new_landmark_max_row_fraction * (config_.height - 1);
  return std::min(config_.height, static_cast<int>(last) + kStoredPatchRadius + 3);
}

void FramePipeline::remove_landmark(LandmarkEstimator& est, int slot) {
  est.delete_landmark(slot);
  book_.remove(slot);
  patches_.clear(slot);
  ++report_.deleted;
}

void FramePipeline::do_initialize(LandmarkEstimator& est) {
  const int end = std::min(new_corner_count_, cursor_ + config_.initializations_per_step);
  for (; cursor_ < end && new_count_ < new_wanted_; ++cursor_) {
    const Corner& c = detector_.corners()[at(new_corners_, cursor_)];
    if (!capture_patch(image_, c.x, c.y, 1.0, candidate_patch_) ||
        !make_template(candidate_patch_, 1.0, config_.tracker.min_template_std,
                       candidate_template_) ||
        candidate_template_.isotropy < config_.tracker.min_template_isotropy) {
      ++report_.edge_corners;
      continue;
    }
    const int slot = est.initialize_landmark(c.x, c.y);
    if (slot < 0 || slot >= hal::kMaxLandmarks) {
      continue;
    }
    // The depth the estimator assumed at initialization goes with the patch (scale prediction).
    PixelPrediction pred;
    const bool predicted = est.predict_pixel(slot, pred);
    if (!predicted || !patches_.capture(slot, image_, c.x, c.y, pred.depth_m)) {
      est.delete_landmark(slot);
      book_.remove(slot);
      patches_.clear(slot);
      continue;
    }
    Eigen::Vector3d camera;
    if (est.camera_position(camera)) {
      patches_.set_anchor(slot, camera);
    }
    // A reused slot (the estimator replaced a landmark) starts afresh.
    book_.activate(slot);
    at(new_landmarks_, new_count_++) = {slot, c.x, c.y};
    ++report_.initialized;
  }
  if (cursor_ >= new_corner_count_ || new_count_ >= new_wanted_) {
    stage_ = FrameStage::kDone;
  }
}

}  // namespace cleanslam::slam_core::frontend
