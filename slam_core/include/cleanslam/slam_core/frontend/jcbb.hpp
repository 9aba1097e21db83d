#pragma once

#include <array>
#include <cstddef>

#include "cleanslam/hal/capacities.hpp"

namespace cleanslam::slam_core::frontend {

struct JcbbConfig {
  // Probability of the chi-square bounds (individual: 2 dof; joint: 2k dof).
  double confidence = 0.99;
  // Fewer jointly compatible observations than this: no update for the frame (Section 3.5).
  int min_inliers = 3;
};

struct JcbbResult {
  int inlier_count = 0;
  // Joint normalized innovation squared of the accepted set.
  double joint_nis = 0.0;
  // inlier_count >= min_inliers.
  bool update = false;
  // Observations dropped before the search: non-finite input or individually incompatible.
  int rejected_individually = 0;
  // Nodes of the interpretation tree visited.
  int nodes = 0;
};

// Simplified joint compatibility branch and bound (Neira and Tardos 2001; Section 3.5): each
// landmark has one candidate or none, so the search only decides which observations to keep. The
// result is the largest subset whose joint innovation passes the chi-square bound at 2k degrees of
// freedom, the smallest joint NIS among equally large ones. The joint NIS of a growing subset is
// updated through an incremental Cholesky factor of its innovation covariance; no allocation.
class Jcbb {
 public:
  static constexpr int kMaxObservations = hal::kMaxObservationsPerFrame;

  explicit Jcbb(const JcbbConfig& config = {});

  // nu: the 2m stacked pixel innovations (observation i at 2i, 2i+1); S: their 2m x 2m joint
  // covariance, column-major with leading dimension 2m. Writes inlier[i] for i < m. m above
  // kMaxObservations (or negative) gives no inliers.
  JcbbResult solve(const double* nu, const double* S, int m, bool* inlier);

  [[nodiscard]] double joint_bound(int observations) const {
    return bounds_[static_cast<std::size_t>(observations)];
  }
  [[nodiscard]] const JcbbConfig& config() const { return config_; }

 private:
  static constexpr int kDim = 2 * kMaxObservations;

  bool try_add(int depth, int obs, double nis, double& nis_out);
  void visit(int next, int depth, double nis);

  JcbbConfig config_;
  std::array<double, kMaxObservations + 1> bounds_{};
  // Per-solve inputs and state.
  const double* nu_ = nullptr;
  const double* S_ = nullptr;
  int ld_ = 0;
  int candidate_count_ = 0;
  std::array<int, kMaxObservations> candidates_{};
  std::array<int, kMaxObservations> chosen_{};
  std::array<int, kMaxObservations> best_{};
  int best_count_ = 0;
  double best_nis_ = 0.0;
  int nodes_ = 0;
  // Lower-triangular Cholesky factor of the chosen observations' covariance, row-major, and
  // L^-1 nu of the chosen innovations.
  std::array<double, std::size_t{kDim} * kDim> L_{};
  std::array<double, kDim> y_{};
};

}  // namespace cleanslam::slam_core::frontend
