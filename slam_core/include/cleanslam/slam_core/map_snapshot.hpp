#pragma once

#include "cleanslam/hal/map_file.hpp"
#include "cleanslam/slam_core/slam_system.hpp"

namespace cleanslam::slam_core {

// The map a run leaves for the next one (hal/map_file.hpp): every landmark in use, its position and
// marginal covariance, its track id (feature frames) or slot (image frames), and, with image
// frames, the first-sighting patch the front end finds it by. The dock is the origin of the map's
// frame: the body pose where this run's map began. Allocates nothing.
void snapshot_map(const SlamSystem& system, hal::TimeNs t_ns, hal::map_file::MapSnapshot& out);

}  // namespace cleanslam::slam_core
