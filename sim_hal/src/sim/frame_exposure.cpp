#include "cleanslam/sim_hal/sim/frame_exposure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace cleanslam::sim_hal::sim {

FrameExposure::FrameExposure(const Scenario::Camera& camera, const Pose3& body_to_camera)
    : camera_(camera),
      body_to_camera_(body_to_camera),
      auto_exposure_(camera.auto_exposure_target, camera.auto_exposure_step_ev) {}

void FrameExposure::render(Renderer& renderer, const Trajectory& trajectory, double t, Random& rng,
                           readers::GrayImage& out) {
  const auto& c = camera_;
  illumination_ *= std::exp(rng.gaussian(c.exposure_walk));
  if (rng.chance(c.exposure_jump_probability)) {
    illumination_ *= rng.uniform(0.7, 1.3);
  }
  illumination_ = std::clamp(illumination_, 0.5, 1.6);
  poses_.clear();
  if (c.exposure_time_s > 0.0) {
    // Centred on the frame's instant, so that features.csv (at the instant) and the image agree
    // on average.
    const int n = std::max(1, c.exposure_samples);
    for (int i = 0; i < n; ++i) {
      const double ti = t + c.exposure_time_s * ((i + 0.5) / n - 0.5);
      poses_.push_back(compose(Trajectory::body_pose(trajectory.at(ti)), body_to_camera_));
    }
  } else {
    poses_.push_back(compose(Trajectory::body_pose(trajectory.at(t)), body_to_camera_));
  }
  const double gain = c.auto_exposure ? auto_exposure_.gain() : 1.0;
  renderer.render(poses_, illumination_ * gain, rng, out, gain);
  if (c.auto_exposure) {
    double sum = 0.0;
    for (const std::uint8_t p : out.pixels) {
      sum += p;
    }
    auto_exposure_.update(sum / static_cast<double>(std::max<std::size_t>(1, out.pixels.size())));
    min_steps_ = std::min(min_steps_, auto_exposure_.steps());
    max_steps_ = std::max(max_steps_, auto_exposure_.steps());
  }
}

double FrameExposure::min_gain() const {
  return std::exp2(min_steps_ * camera_.auto_exposure_step_ev);
}

double FrameExposure::max_gain() const {
  return std::exp2(max_steps_ * camera_.auto_exposure_step_ev);
}

}  // namespace cleanslam::sim_hal::sim
