#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "cleanslam/hal/capacities.hpp"

// What one EKF call did with each observation, in the spirit of PX4's aid-source status.
namespace cleanslam::slam_core {

enum class ObservationResult : std::uint8_t {
  kFused = 0,
  kNonFinite,            // pixel, or a result, not finite
  kOutOfImage,           // pixel outside the image, or undistortion did not converge
  kBehindCamera,         // landmark not in front of the camera
  kGate,                 // chi-square test failed
  kParallelRay,          // ray along the direction of travel (initialization)
  kNotPositiveDefinite,  // innovation covariance or posterior not positive definite
  kInvalidSlot,          // slot out of range or not in use, or observed twice in one frame
  kOverCapacity,         // more observations than hal::kMaxObservationsPerFrame
  kDepthBound,           // the update would move the landmark behind the camera or past max depth
  kOutOfRange,           // a result beyond Ekf::kMaxAbsState or Ekf::kMaxVariance
  kCount
};

inline constexpr int kObservationResultCount = static_cast<int>(ObservationResult::kCount);

const char* to_string(ObservationResult r);

struct ObservationStatus {
  int slot = -1;
  Eigen::Vector3d innovation = Eigen::Vector3d::Zero();  // z - h, camera frame, m
  Eigen::Matrix3d innovation_covariance = Eigen::Matrix3d::Zero();
  double test_ratio = 0.0;  // nu^T S^-1 nu / gate; fused only when <= 1
  Eigen::Vector2d pixel_innovation = Eigen::Vector2d::Zero();  // measured - predicted pixel
  double pixel_test_ratio = 0.0;  // the same test on pixels (EkfConfig::gate_pixel_chi2)
  ObservationResult result = ObservationResult::kFused;
  [[nodiscard]] bool fused() const { return result == ObservationResult::kFused; }
};

struct UpdateStatus {
  std::array<ObservationStatus, hal::kMaxObservationsPerFrame> observations{};
  int count = 0;     // records filled in `observations`
  int received = 0;  // observations passed in
  int fused = 0;
  int rejected = 0;
  bool applied = false;  // the state changed
};

// One scalar update of an odometry measurement (a direction of the turns' difference): its
// innovation and the innovation's variance, in the measurement's whitened units, the test ratio
// innovation^2 / variance (chi-square, 1 dof), and whether it was fused or gated.
// Counts by reason since construction (indexed by ObservationResult).
struct RejectionCounters {
  std::array<std::uint64_t, kObservationResultCount> by_reason{};
  [[nodiscard]] std::uint64_t operator[](ObservationResult r) const {
    return by_reason[static_cast<std::size_t>(r)];
  }
  void add(ObservationResult r) { ++by_reason[static_cast<std::size_t>(r)]; }
};

enum class PredictResult : std::uint8_t {
  kApplied = 0,
  kNonFinite,
  kPitchSingular,
  kNotPositiveDefinite,
  kOutOfRange  // the predicted pose or a variance beyond Ekf::kMaxAbsState or Ekf::kMaxVariance
};

struct PredictStatus {
  PredictResult result = PredictResult::kApplied;
  [[nodiscard]] bool applied() const { return result == PredictResult::kApplied; }
};

}  // namespace cleanslam::slam_core
