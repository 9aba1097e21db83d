#pragma once

#include <vector>

#include "cleanslam/readers/gray_image.hpp"
#include "cleanslam/sim_hal/sim/camera_effects.hpp"
#include "cleanslam/sim_hal/sim/random.hpp"
#include "cleanslam/sim_hal/sim/renderer.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/sim_math.hpp"
#include "cleanslam/sim_hal/sim/trajectory.hpp"

// How the simulator exposes each camera frame, in order: the illumination drifts and jumps
// (camera.exposure_walk, exposure_jump_probability), the light is integrated over the camera
// poses of the exposure time (motion blur), and the auto exposure steps its gain after the frame.
namespace cleanslam::sim_hal::sim {

class FrameExposure {
 public:
  FrameExposure(const Scenario::Camera& camera, const Pose3& body_to_camera);

  // Renders the frame whose instant is path time `t`; `rng` is the image stream.
  void render(Renderer& renderer, const Trajectory& trajectory, double t, Random& rng,
              readers::GrayImage& out);

  // The auto exposure's gain range so far (1 without auto exposure).
  [[nodiscard]] double min_gain() const;
  [[nodiscard]] double max_gain() const;

 private:
  Scenario::Camera camera_;
  Pose3 body_to_camera_;
  double illumination_ = 1.0;
  AutoExposure auto_exposure_;
  int min_steps_ = 0;
  int max_steps_ = 0;
  std::vector<Pose3> poses_;
};

}  // namespace cleanslam::sim_hal::sim
