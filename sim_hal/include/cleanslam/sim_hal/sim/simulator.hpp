#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/frame.hpp"
#include "cleanslam/readers/result.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/sim_math.hpp"
#include "cleanslam/sim_hal/sim/world.hpp"

namespace cleanslam::sim_hal::sim {

// The independent generator streams of one seed (Random's `stream`), one per part of the world or
// sensor. A tool that regenerates part of a simulation (cleanslam-frontend-truth) draws from these.
namespace stream {
inline constexpr std::uint64_t kWorld = 1;
inline constexpr std::uint64_t kPath = 2;
inline constexpr std::uint64_t kGyro = 3;
inline constexpr std::uint64_t kEncoders = 4;
inline constexpr std::uint64_t kCamera = 5;
inline constexpr std::uint64_t kImage = 6;
}  // namespace stream

// The camera optical frame (z forward, x right, y down) in the body frame: `forward_m` ahead of
// the wheel axis, `height_m` above the floor, pitched up by `tilt_deg`.
Pose3 body_to_camera(const Scenario::Camera& camera);
// What sensors.yaml says: the nominal values the robot's firmware would be configured with (the
// true wheel scale and wheel base differ by the scenario's errors).
hal::Calibration calibration_of(const Scenario& scenario);

// Writes sim_truth.yaml: the true wheel constants (the nominal ones with the scenario's scale and
// wheel base errors applied), the gyro's noise and bias and the camera's intrinsics.
readers::Status write_sim_truth(const Scenario& scenario, const std::string& path);

// Pinhole projection with radial-tangential distortion; false when behind the camera.
bool project(const Scenario::Camera& camera, Vec3 p_cam, double& u, double& v);

// The noise-free pixel observations of the landmarks visible from camera pose `world_camera`.
struct Visible {
  const Landmark* landmark;
  double u;
  double v;
  double range;
};
std::vector<Visible> visible_landmarks(const Scenario::Camera& camera, const World& world,
                                       const std::vector<Landmark>& landmarks,
                                       const Pose3& world_camera);

struct SimulationSummary {
  double duration_s = 0.0;
  double path_length_m = 0.0;
  int landmarks = 0;
  int frames = 0;
  int frames_without_features = 0;
  double mean_features = 0.0;
  double fraction_frames_5_to_10 = 0.0;  // frames with 5..10 static landmarks in view
  double fraction_frames_5_or_more = 0.0;
  double longest_gap_s = 0.0;  // longest time without any static landmark in view
  int gyro_samples = 0;
  int encoder_samples = 0;
  int slip_events = 0;
  std::string images;  // images mode: the textures in use (and why not photographs), gain range
};

// Simulates the scenario and writes a dataset folder (docs/dataset-format.md) plus
// sim_landmarks.csv (#id,x_m,y_m,z_m: the true static landmarks, not part of the format).
// `progress` (optional) receives the fraction done.
readers::Result<SimulationSummary> simulate(const Scenario& scenario, const std::string& out_dir,
                                            const std::function<void(double)>& progress = {});

}  // namespace cleanslam::sim_hal::sim
