#include "cleanslam/paper_models/landmark_model.hpp"

namespace cleanslam::paper_models {

ModelStatus LandmarkModel::counted(ModelStatus status) {
  switch (status) {
    case ModelStatus::kOk:
      break;
    case ModelStatus::kNonFiniteInput:
      ++rejections_.non_finite_input;
      break;
    case ModelStatus::kBehindCamera:
      ++rejections_.behind_camera;
      break;
    case ModelStatus::kSingularInnovation:
      ++rejections_.singular_innovation;
      break;
    case ModelStatus::kNotInitialized:
      ++rejections_.not_initialized;
      break;
    case ModelStatus::kUnsupportedMotion:
      ++rejections_.unsupported_motion;
      break;
    case ModelStatus::kRejectedByFilter:
      ++rejections_.rejected_by_filter;
      break;
  }
  return status;
}

bool is_finite(const KnownPose& pose) {
  return pose.position_w.allFinite() && pose.C_wc.allFinite();
}

}  // namespace cleanslam::paper_models
