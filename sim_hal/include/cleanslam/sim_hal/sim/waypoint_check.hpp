#pragma once

#include <string>
#include <vector>

#include "cleanslam/sim_hal/sim/scenario.hpp"

// What keeps a scenario's waypoint path drivable: every point inside the world, robot.radius clear
// of its walls, and no straight run between two points through a furniture box (at its moved
// place) or an interior wall grown by robot.radius.
namespace cleanslam::sim_hal::sim {

// One message per fault, naming the key (path.waypoints[i], the segment [i] -> [i + 1] and the
// box it runs through); empty when the path is drivable.
std::vector<std::string> waypoint_path_errors(const Scenario& scenario);

}  // namespace cleanslam::sim_hal::sim
