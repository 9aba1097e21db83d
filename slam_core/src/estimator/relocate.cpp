#include "cleanslam/slam_core/ekf.hpp"

namespace cleanslam::slam_core {

bool Ekf::relocate(const Vector6d& camera_pose) {
  if (!camera_pose.allFinite() || update_pending()) {
    return false;
  }
  x_.head<6>() = camera_pose;
  x_(5) = wrap_angle(x_(5));
  return true;
}

}  // namespace cleanslam::slam_core
