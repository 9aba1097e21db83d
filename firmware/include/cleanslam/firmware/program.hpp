#pragma once

#include <memory>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/estimator.hpp"
#include "cleanslam/firmware/loop.hpp"

namespace cleanslam::firmware {

// The EKF SLAM estimator for a configuration (slam_estimator.cpp).
std::unique_ptr<Estimator> make_estimator(const FirmwareConfig& config);

// The loop's options of a configuration, with the calibrated image size frames must have.
LoopOptions loop_options(const FirmwareConfig& config);

// `cleanslam`: argument parsing, configuration, wiring, the run, --replay.
int program_main(int argc, char** argv);

}  // namespace cleanslam::firmware
