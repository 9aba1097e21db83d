#include "cleanslam/slam_core/version.hpp"

namespace cleanslam::slam_core {

const char* version() {
  return "0.1.0";
}

}  // namespace cleanslam::slam_core
