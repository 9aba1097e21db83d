#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/estimator.hpp"
#include "cleanslam/firmware/loop.hpp"

namespace cleanslam::firmware {

// The EKF SLAM estimator for a configuration (slam_estimator.cpp).
std::unique_ptr<Estimator> make_estimator(const FirmwareConfig& config);

// The loop's options of a configuration, with the calibrated image size frames must have.
LoopOptions loop_options(const FirmwareConfig& config);

// Counts of a finished run, one line per non-zero counter, for stderr.
void print_summary(const Loop& loop, std::FILE* out);

// Writes landmarks.csv: slot,x,y,z,sxx,sxy,sxz,syy,syz,szz.
bool write_landmarks_csv(const Estimator& estimator, const std::string& path, std::string& error);

// `cleanslam`: argument parsing, configuration, wiring, the run, --replay.
int program_main(int argc, char** argv);

}  // namespace cleanslam::firmware
