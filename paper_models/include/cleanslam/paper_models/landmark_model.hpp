#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "cleanslam/paper_models/image_plane.hpp"

namespace cleanslam::paper_models {

enum class ModelStatus : std::uint8_t {
  kOk,
  kNonFiniteInput,
  kBehindCamera,
  kSingularInnovation,
  kNotInitialized,
  kUnsupportedMotion,
  kRejectedByFilter,
};

struct RejectionCounts {
  std::uint32_t non_finite_input = 0;
  std::uint32_t behind_camera = 0;
  std::uint32_t singular_innovation = 0;
  std::uint32_t not_initialized = 0;
  std::uint32_t unsupported_motion = 0;
  std::uint32_t rejected_by_filter = 0;
};

// One landmark seen from a known camera pose: the interface the paper's comparison (Section 4.3)
// runs every model through. Rejected input leaves the estimate unchanged and is counted.
class LandmarkModel {
 public:
  virtual ~LandmarkModel() = default;

  virtual ModelStatus initialize(const KnownPose& pose, const Eigen::Vector2d& pixel) = 0;
  virtual ModelStatus update(const KnownPose& pose, const Eigen::Vector2d& pixel) = 0;
  virtual Eigen::Vector3d position_w() const = 0;
  virtual Eigen::Matrix3d covariance_w() const = 0;

  const RejectionCounts& rejections() const { return rejections_; }

 protected:
  ModelStatus counted(ModelStatus status);

 private:
  RejectionCounts rejections_;
};

bool is_finite(const KnownPose& pose);

}  // namespace cleanslam::paper_models
