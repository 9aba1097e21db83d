#pragma once

#include <vector>

#include "cleanslam/readers/gray_image.hpp"
#include "cleanslam/sim_hal/sim/random.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/sim_math.hpp"

// camera.mode checkerboard: views of a planar checkerboard for the camera's calibration
// (tools/calibrate camera), rendered through the scenario's own camera model (pixel_ray, project),
// so that a calibration can be checked against the scenario's intrinsics and distortion.
namespace cleanslam::sim_hal::sim {

// The board's pose in the camera's optical frame for view `index`: tilted up to about 35 degrees
// either way, 0.4-0.8 m away, its centre moved over the image so that the views' corners cover
// it, always wholly in view. The board's frame: origin at its first inner corner, x along
// `cols`, y along `rows`, z into the board.
Pose3 checkerboard_pose(const Scenario& scenario, int index, Random& rng);

// The board's pose in the camera's optical frame when it lies on the floor (checkerboard.on_floor),
// seen through the camera's mount (body_to_camera).
Pose3 checkerboard_on_floor_pose(const Scenario& scenario);

// Renders the board (with a white border one square wide, on a grey background): 16 rays per
// pixel, traced once through the camera model at construction; camera.image_noise gray levels of
// noise.
class CheckerboardRenderer {
 public:
  explicit CheckerboardRenderer(const Scenario& scenario);
  void render(const Pose3& camera_board, Random& rng, readers::GrayImage& out) const;

 private:
  Scenario::Camera camera_;
  Scenario::Checkerboard board_;
  std::vector<Vec3> rays_;  // 16 per pixel, row by row
};

}  // namespace cleanslam::sim_hal::sim
