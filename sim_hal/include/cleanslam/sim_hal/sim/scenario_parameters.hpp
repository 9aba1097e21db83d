#pragma once

#include <span>
#include <string>

#include "cleanslam/hal/parameter.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"

// A scenario's keys (hal/parameter.hpp), each once with its default, range, unit and meaning.
// The sequences (world.furniture, world.walls, world.moved, path.stops, path.waypoints) and the
// keys that are unset by default (world.seed, checkerboard.on_floor) are read by load_scenario
// itself.
namespace cleanslam::sim_hal::sim {

std::span<const hal::Parameter<Scenario>> scenario_parameters();

// Every key of the table with its default, range, unit and meaning, as a scenario file writes
// it (cleanslam-sim --keys).
std::string scenario_keys_text();

}  // namespace cleanslam::sim_hal::sim
