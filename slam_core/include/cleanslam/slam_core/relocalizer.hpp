#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/image.hpp"
#include "cleanslam/slam_core/camera_model.hpp"
#include "cleanslam/slam_core/frontend/harris.hpp"
#include "cleanslam/slam_core/frontend/patch.hpp"
#include "cleanslam/slam_core/geometry.hpp"
#include "cleanslam/slam_core/relocalizer_config.hpp"

namespace cleanslam::slam_core {

// Relocalization after the robot was carried further than the filter's pose covariance says:
// the earlier map's landmarks are looked for among the frame's corners by appearance (each
// first-sighting patch at the scale the corner's elevation implies: the landmark's height is
// mapped, so the elevation gives its distance from the camera), and
// planar camera poses (x, y, yaw; height, roll and pitch are the filter's) are hypothesized from
// pairs of candidate sightings (each candidate's bearing and elevation give its horizontal
// position from the camera) and scored by the landmarks that project onto their candidates.
// Resumable, bounded work per step; allocates nothing.
class Relocalizer {
 public:
  Relocalizer(const CameraModel& camera, const RelocalizerConfig& config = {});

  // A frame: its image and corners (both stay valid until solved) and the filter's camera pose.
  void begin(const hal::GrayImageView& image, const frontend::Corner* corners, int corner_count,
             const Vector6d& camera_pose);
  // An earlier landmark and its first-sighting patch (both stay valid until solved): its
  // candidate sightings.
  void add_landmark(int slot, const Eigen::Vector3d& position,
                    const frontend::LandmarkPatch& patch);
  // One bounded part of the pose search; true when it is complete.
  bool search_step();
  // The pose found (camera pose in the world), with inliers() landmarks; false when none.
  [[nodiscard]] bool found(Vector6d& camera_pose) const;
  [[nodiscard]] int inliers() const { return best_score_; }
  [[nodiscard]] int candidate_count() const { return candidate_count_; }
  // The best pose's check by appearance: of the other landmarks it puts in view (at most
  // kMaxChecked), how many match their patch near where they project.
  [[nodiscard]] int checked() const { return checked_; }
  [[nodiscard]] int confirmed() const { return confirmed_; }

 private:
  struct Candidate {
    int slot = -1;
    Eigen::Vector3d landmark = Eigen::Vector3d::Zero();
    double u_px = 0.0;
    double v_px = 0.0;
    Eigen::Vector2d q = Eigen::Vector2d::Zero();  // horizontal position from the camera, level
    bool has_q = false;
    float ncc = 0.0F;
  };
  static constexpr int kMaxCandidates = 96;
  static constexpr int kMaxChecked = 24;
  // A corner's ray levelled by the filter's roll and pitch: its horizontal direction and the
  // tangent of its elevation.
  struct LevelRay {
    Eigen::Vector2d direction = Eigen::Vector2d::Zero();
    double tan_elevation = 0.0;
    bool valid = false;
  };

  [[nodiscard]] float ncc_at(const frontend::PatchTemplate& tmpl, double u, double v) const;
  bool level_position(int corner, const Eigen::Vector3d& landmark, Eigen::Vector2d& q) const;
  // Which of kScaleSteps the landmark's patch takes at each corner (-1: the corner's distance is
  // not known, kUnknownDistanceSteps are tried).
  void assign_scale_steps(const Eigen::Vector3d& landmark, const frontend::LandmarkPatch& patch);
  int score(double x, double y, double yaw);
  // checked_ and confirmed_ of the best pose, landmarks_per_step landmarks per call; true when
  // complete.
  bool check_best();
  // Landmarks the last hypothesis shares with the best one.
  [[nodiscard]] int shared_with_best() const;
  void consider(const Candidate& c);

  const CameraModel& camera_;
  RelocalizerConfig config_;
  hal::GrayImageView image_;
  const frontend::Corner* corners_ = nullptr;
  int corner_count_ = 0;
  Vector6d pose_ = Vector6d::Zero();
  Eigen::Matrix3d R_rp_ = Eigen::Matrix3d::Identity();  // roll and pitch of the camera
  std::array<LevelRay, hal::kMaxCorners> rays_{};
  std::array<int, hal::kMaxCorners> scale_step_{};
  std::array<Candidate, kMaxCandidates> candidates_{};
  int candidate_count_ = 0;
  std::array<bool, hal::kMaxLandmarks> counted_{};  // the last hypothesis's inliers
  std::array<bool, hal::kMaxLandmarks> best_inliers_{};
  frontend::PatchTemplate template_;
  struct Added {
    int slot = -1;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    const frontend::LandmarkPatch* patch = nullptr;
  };
  std::array<Added, hal::kMaxLandmarks> added_{};
  int added_count_ = 0;
  int checked_ = 0;
  int confirmed_ = 0;
  int check_cursor_ = 0;  // the next of added_ check_best() looks at
  int row_ = 0;
  int best_score_ = 0;
  Vector6d best_ = Vector6d::Zero();
  int second_score_ = 0;
};

}  // namespace cleanslam::slam_core
