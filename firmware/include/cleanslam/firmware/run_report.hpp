#pragma once

#include <cstdio>
#include <string>

#include "cleanslam/firmware/camera_offset_estimate.hpp"
#include "cleanslam/firmware/estimator.hpp"
#include "cleanslam/firmware/loop.hpp"

// What a finished run reports: its counters and the estimator's findings, and the map it made.
namespace cleanslam::firmware {

// Counts of a finished run, one line per non-zero counter, and the camera time offset the data
// suggest, for stderr.
void print_summary(const Loop& loop, const CameraOffsetEstimate& camera_offset, std::FILE* out);

// Writes landmarks.csv: slot,x,y,z,sxx,sxy,sxz,syy,syz,szz.
bool write_landmarks_csv(const Estimator& estimator, const std::string& path, std::string& error);

}  // namespace cleanslam::firmware
