#pragma once

#include <cstddef>

// Every capacity of the firmware is a compile-time constant, in this one header.
namespace cleanslam::hal {

inline constexpr int kImageWidth = 320;
inline constexpr int kImageHeight = 240;

// Landmark slots of the EKF map (the pool of Sola's toolbox).
inline constexpr int kMaxLandmarks = 128;
// Observations fused in one camera frame (Section 3.2 keeps 5-10 in view).
inline constexpr int kMaxObservationsPerFrame = 16;
// Pixel observations a frame may carry from an external front end (features.csv mode).
inline constexpr int kMaxFeaturesPerFrame = 64;
// Corner candidates kept by the detector per frame.
inline constexpr int kMaxCorners = 256;

inline constexpr int kPoseDim = 6;
inline constexpr int kLandmarkDim = 3;
inline constexpr int kMaxStateDim = kPoseDim + kLandmarkDim * kMaxLandmarks;

}  // namespace cleanslam::hal
