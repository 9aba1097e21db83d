#pragma once

namespace cleanslam::slam_core {

const char* version();

}  // namespace cleanslam::slam_core
