#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/image.hpp"
#include "cleanslam/slam_core/frontend/harris.hpp"
#include "cleanslam/slam_core/frontend/image_check.hpp"
#include "cleanslam/slam_core/frontend/jcbb.hpp"
#include "cleanslam/slam_core/frontend/landmark_book.hpp"
#include "cleanslam/slam_core/frontend/landmark_estimator.hpp"
#include "cleanslam/slam_core/frontend/patch.hpp"
#include "cleanslam/slam_core/frontend/search_region.hpp"
#include "cleanslam/slam_core/frontend/tracker.hpp"

namespace cleanslam::slam_core::frontend {

struct FramePipelineConfig {
  int width = hal::kImageWidth;
  int height = hal::kImageHeight;
  HarrisConfig harris;
  TrackerConfig tracker;
  SearchRegionConfig region;
  JcbbConfig jcbb;
  LandmarkBookConfig book;
  // Two landmarks matched closer than this keep only the better match.
  double duplicate_px = 3.0;
  // A landmark is searched only while its view is like the first sighting's (Davison's
  // "predicted to be measurable"): its distance within a factor max_view_scale of the first one,
  // and the angle between the two viewing rays with a cosine of at least min_view_cos. Otherwise
  // its patch would not match, and a miss would be held against it, deleting the landmark before
  // the robot comes back to where it can be found again (loop closure).
  double max_view_scale = 1.8;
  double min_view_cos = 0.82;  // 35 degrees
  // New landmarks are taken only above this fraction of the image height. The default suits a
  // camera close to the floor looking ahead: below, the floor is seen at grazing angles (its
  // patches deform with every move) and its junction with walls and furniture makes corners that
  // slide along it (occlusion boundaries). 1: the whole image.
  double new_landmark_max_row_fraction = 0.7;
  // A landmark not matched for more frames than this is reacquired (Tracker::track): the pose
  // may have drifted more than its covariance says, and a look-alike near the prediction must
  // not close the loop.
  int reacquire_after_frames = 10;
  // Bounded work per step().
  int detect_rows_per_step = 60;
  int predictions_per_step = 16;
  int tracks_per_step = 4;
  int initializations_per_step = 4;
};

// The stages of one frame, in order; step() does a bounded part of the current one.
enum class FrameStage : std::uint8_t {
  kIdle,
  kDetect,      // Harris corners of the whole frame
  kPredict,     // predicted pixels and search regions of the active landmarks
  kTrack,       // a few landmarks per step
  kAssociate,   // joint innovation and JCBB
  kUpdate,      // estimator update with the inliers
  kFuse,        // the rest of that update, when the estimator bounds its work per call
  kManage,      // delete landmarks that keep failing
  kInitialize,  // new landmarks where none is in view, a few per step
  kDone,
};

// One landmark searched in this frame.
struct TrackRecord {
  int slot = -1;
  SearchRegion region;
  double predicted_depth_m = 0.0;
  // The landmark's position estimate and its distance from the camera (for the patch scale).
  Eigen::Vector3d landmark = Eigen::Vector3d::Zero();
  double distance_m = 0.0;
  bool has_distance = false;
  TrackResult result;
  bool inlier = false;
  // The predicted pixel itself is inside the searchable image; a landmark predicted beyond the
  // border is still searched where its region overlaps the image, but a miss is not held
  // against it (it may simply have left the view).
  bool center_inside = false;
  int priority = 0;  // who keeps a track when there are more candidates than tracks
};

struct FrameReport {
  ImageCheck image_check = ImageCheck::kOk;
  bool featureless = false;  // no corner: nothing tracked, nothing counted against landmarks
  int corners = 0;
  int predicted = 0;
  int in_view = 0;      // predicted inside the searchable image
  int unmatchable = 0;  // predicted, but seen too differently from the first sighting
  int searched = 0;     // regions searched (in view, and those overlapping the border)
  int tracked = 0;
  int duplicates = 0;
  int inliers = 0;
  int outliers = 0;
  bool innovation_rejected = false;  // the estimator refused the joint innovation
  bool updated = false;
  int fused = 0;
  int deleted = 0;
  int initialized = 0;
  int edge_corners = 0;  // corners not taken as landmarks: their patch is an edge
  int steps = 0;
  JcbbResult jcbb;
};

// The vision front end of one camera frame as resumable steps (detect, predict regions, track a
// few landmarks, associate, update, manage the map), each with a bounded amount of work, so that
// the cooperative loop can interleave gyro and encoder samples between them. The image passed to
// begin_frame must stay valid until the frame is done. No allocation after construction.
class FramePipeline {
 public:
  explicit FramePipeline(const FramePipelineConfig& config = {});

  // Forgets every landmark and patch and abandons the frame in progress, as when the estimator
  // starts a new map (the robot set down after a lift). Allocates nothing.
  void forget_map();
  // Every landmark leaves the search (its patch is kept): the map is not where the pose says
  // (relocalizing after a set-down).
  void suspend_map();
  // A suspended landmark is searched again (LandmarkBook::resume).
  void resume(int slot);
  // A landmark the map's management deleted.
  void forget(int slot);

  // Starts a frame. A wrong image is rejected (the report says why; describe() words it) and the
  // frame is done at once. allow_update false (robot standing still, Section 2.4) tracks and
  // manages the map but does not update the estimator.
  ImageCheck begin_frame(const hal::GrayImageView& image, bool allow_update = true);
  // One bounded step; true while the frame has more work.
  bool step(LandmarkEstimator& estimator);
  // All remaining steps.
  const FrameReport& finish(LandmarkEstimator& estimator);

  [[nodiscard]] FrameStage stage() const { return stage_; }
  [[nodiscard]] const FrameReport& report() const { return report_; }
  // The frame's image check in words (names the sizes at fault).
  const char* describe(char* out, std::size_t out_size) const;

  [[nodiscard]] const TrackRecord* tracks() const { return tracks_.data(); }
  [[nodiscard]] int track_count() const { return track_count_; }
  [[nodiscard]] const HarrisDetector& detector() const { return detector_; }
  [[nodiscard]] const LandmarkBook& book() const { return book_; }
  [[nodiscard]] const PatchStore& patches() const { return patches_; }
  // Landmarks initialized this frame and the pixels they were taken at.
  [[nodiscard]] int new_landmark_count() const { return new_count_; }
  [[nodiscard]] const PixelObservation& new_landmark(int i) const {
    return new_landmarks_[static_cast<std::size_t>(i)];
  }

 private:
  void do_detect();
  void do_predict(LandmarkEstimator& est);
  void do_track();
  [[nodiscard]] bool matchable(int slot, const Eigen::Vector3d& landmark) const;
  [[nodiscard]] double patch_scale(const LandmarkPatch& patch, const TrackRecord& t) const;
  void do_associate(LandmarkEstimator& est);
  void do_update(LandmarkEstimator& est);
  void do_fuse(LandmarkEstimator& est);
  void do_manage(LandmarkEstimator& est);
  void do_initialize(LandmarkEstimator& est);
  void remove_landmark(LandmarkEstimator& est, int slot);
  [[nodiscard]] int new_landmark_rows() const;

  FramePipelineConfig config_;
  HarrisDetector detector_;
  PatchStore patches_;
  Tracker tracker_;
  Jcbb jcbb_;
  LandmarkBook book_;

  hal::GrayImageView image_;
  bool allow_update_ = true;
  FrameStage stage_ = FrameStage::kIdle;
  FrameReport report_;
  int cursor_ = 0;
  Eigen::Vector3d camera_ = Eigen::Vector3d::Zero();  // camera position estimate this frame
  bool camera_known_ = false;

  static constexpr int kMaxTracks = hal::kMaxObservationsPerFrame;
  std::array<TrackRecord, kMaxTracks> tracks_{};
  int track_count_ = 0;
  // Active landmarks predicted inside the image but beyond kMaxTracks: not searched this frame.
  std::array<double, hal::kMaxLandmarks> occupied_u_{};
  std::array<double, hal::kMaxLandmarks> occupied_v_{};
  int occupied_count_ = 0;

  std::array<PixelObservation, kMaxTracks> obs_{};
  std::array<int, kMaxTracks> obs_track_{};  // index into tracks_
  int obs_count_ = 0;
  std::array<double, std::size_t{2} * kMaxTracks> nu_{};
  std::array<double, std::size_t{4} * kMaxTracks * kMaxTracks> S_{};
  std::array<bool, kMaxTracks> inlier_{};
  std::array<bool, hal::kMaxLandmarks> matched_now_{};

  std::array<int, hal::kMaxCorners> new_corners_{};
  int new_corner_count_ = 0;
  int new_wanted_ = 0;
  // A candidate's patch and template, checked before it becomes a landmark.
  LandmarkPatch candidate_patch_;
  PatchTemplate candidate_template_;
  std::array<PixelObservation, hal::kMaxCorners> new_landmarks_{};
  int new_count_ = 0;
};

}  // namespace cleanslam::slam_core::frontend
