#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "cleanslam/hal/time.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/result.hpp"

// Trajectory evaluation (cleanslam-eval): estimates in TUM format against a dataset's ground
// truth.
//
// Covariance side file, FILE.tum.cov next to FILE.tum: one line per estimate, "#" comments
// allowed, whitespace- or comma-separated: t (seconds, as in the TUM file) followed by either
// 9 numbers (the 3x3 position covariance, row-major, m^2) or 36 numbers (the 6x6 covariance over
// x, y, z, roll, pitch, yaw of hal::PoseEstimate, row-major; its top-left 3x3 is used). Lines are
// matched to poses by time stamp (within 1 microsecond); poses without one get no NEES.
namespace cleanslam::evaluation {

struct TumPose {
  hal::TimeNs t_ns = 0;
  std::array<double, 3> position{};
  std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};
  std::optional<std::array<double, 9>> position_covariance;
};

// "t x y z qx qy qz qw" per line, t in seconds; sorted by time, quaternions normalized.
readers::Result<std::vector<TumPose>> read_tum(const std::string& path);
// Attaches the covariances of `path` (see above) to `poses`.
readers::Status read_covariances(const std::string& path, std::vector<TumPose>& poses);

enum class Alignment { kNone, kSe2, kSe3 };

struct Metrics {
  int poses_evaluated = 0;
  int poses_outside_groundtruth = 0;  // estimates before the first or after the last GT pose
  double ate_rmse_m = 0.0;            // absolute trajectory error (positions), after alignment
  double ate_max_m = 0.0;
  double orientation_rmse_deg = 0.0;
  double final_error_m = 0.0;  // position error of the last evaluated pose
  double path_length_m = 0.0;  // ground truth, over the evaluated span
  // Relative pose error over pairs of poses 1 m of ground-truth travel apart: RMSE of the
  // translation error divided by the travelled distance (m per m), and of the heading error
  // (deg per m). Zero pairs when the path is shorter than 1 m.
  int rpe_pairs = 0;
  double rpe_translation_per_m = 0.0;
  double rpe_rotation_deg_per_m = 0.0;
  // Position NEES e^T P^-1 e over the poses with a covariance (3 degrees of freedom: mean 3 for
  // a consistent estimator), and the fraction inside the two-sided 95% chi-square bounds.
  int nees_count = 0;
  double nees_mean = 0.0;
  double nees_fraction_in_95 = 0.0;
  // Poses whose covariance is not positive definite (a corrupt file or an estimator's fault):
  // left out of the NEES, counted, and the first one's time (seconds).
  int nees_not_positive_definite = 0;
  double first_not_positive_definite_s = 0.0;
  // The alignment applied (estimate -> ground truth frame): yaw (se2) or rotation, translation.
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::array<double, 3> translation{};
};

// Ground truth interpolated at `t` (linear in position, slerp in orientation), or nullopt outside
// its time span.
std::optional<TumPose> interpolate(const std::vector<readers::GroundTruthPose>& gt, hal::TimeNs t);

// `none`: both trajectories are expressed relative to their first (evaluated) pose and nothing
// more. `se2`: least-squares rotation about z and xy translation (Horn/Umeyama, no scale);
// `se3`: least-squares rotation and translation (Umeyama, no scale).
readers::Result<Metrics> evaluate(const std::vector<readers::GroundTruthPose>& groundtruth,
                                  const std::vector<TumPose>& estimate, Alignment alignment);

std::string to_json(const Metrics& m, Alignment alignment);
std::string to_text(const Metrics& m, Alignment alignment);

}  // namespace cleanslam::evaluation
