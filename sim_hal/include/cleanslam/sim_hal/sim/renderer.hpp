#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cleanslam/readers/gray_image.hpp"
#include "cleanslam/sim_hal/sim/photo_textures.hpp"
#include "cleanslam/sim_hal/sim/random.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/sim_math.hpp"

// The rendered camera mode: ray casting of the room (walls, floor, ceiling, furniture boxes,
// interior walls) with procedural corner-rich textures or photographs, simple shading, exposure
// gain, vignetting, a little blur, motion blur and pixel noise (read and shot), into 8-bit gray
// images of the calibrated size. Four rays per pixel through the (distorted) pinhole, averaged (the
// pixel's area); with motion blur at least one ray per pixel and pose of the exposure.
namespace cleanslam::sim_hal::sim {

// Unit ray (optical frame) of the pixel (u, v) through the pinhole with radial-tangential
// distortion: undistorts (u, v) by fixed-point iteration.
Vec3 pixel_ray(const Scenario::Camera& camera, double u, double v);

class Renderer {
 public:
  explicit Renderer(const Scenario& scenario);

  // Renders the view from `world_camera` (optical frame: z forward, x right, y down) with
  // brightness gain `exposure` (1 = nominal); `rng` draws the pixel noise.
  void render(const Pose3& world_camera, double exposure, Random& rng, readers::GrayImage& out);
  // The same, integrating the light over the camera poses `exposure_poses` (evenly spread over
  // the exposure time): motion blur. `exposure` includes the analog `gain`, which with
  // camera.shot_noise_gain > 0 also amplifies the noise.
  void render(const std::vector<Pose3>& exposure_poses, double exposure, Random& rng,
              readers::GrayImage& out, double gain = 1.0);

  // Whether the surfaces wear photographs (camera.textures = photos and every one was read), and
  // a sentence saying which textures are in use and, if the photographs are missing, why.
  [[nodiscard]] bool photos_in_use() const { return photos_in_use_; }
  [[nodiscard]] const std::string& textures_note() const { return textures_note_; }

  // Albedo in [0, 1] of surface `surface` at surface coordinates (a, b) in metres. Surfaces:
  // 0 floor, 1 ceiling, 2..5 walls, 6.. furniture boxes, then two per interior wall.
  [[nodiscard]] double albedo(int surface, double a, double b) const;
  // The surface seen by pixel (x, y), or -1.
  [[nodiscard]] int surface_at(const Pose3& world_camera, int x, int y) const;

  // What the ray through the sub-pixel position (u, v) (origin at the centre of the top-left
  // pixel, as the calibration's cx, cy) hits: the world point and its surface (-1: nothing).
  // Ground truth for the front end's diagnostics; not used while rendering.
  struct SurfacePoint {
    int surface = -1;
    Vec3 point;
    double distance = 0.0;
  };
  [[nodiscard]] SurfacePoint point_at(const Pose3& world_camera, double u, double v) const;

 private:
  struct Hit {
    double distance;
    int surface;
    double a;
    double b;
    double cos_incidence;
  };
  [[nodiscard]] Hit cast(Vec3 origin, Vec3 dir) const;
  // Albedo from the photographs; `footprint` is the size in metres a pixel covers there.
  [[nodiscard]] double photo_albedo(int surface, double a, double b, double footprint) const;

  Scenario::Camera camera_;
  Vec3 room_;
  std::vector<Box> boxes_;  // furniture at its place, then the interior walls
  int first_wall_surface_;  // surfaces from here on are interior walls (two per wall)
  std::uint64_t seed_;
  double noise_sigma_;
  double blur_;
  double shot_gain_;
  PhotoTextures photos_;
  bool photos_in_use_ = false;
  std::string textures_note_;
  std::vector<float> vignette_;  // per pixel; empty without vignetting
  static constexpr std::size_t kSamples = 4;
  // Sample positions inside a pixel relative to its centre (rotated grid).
  static constexpr double kSampleOffsets[kSamples][2] = {
      {-0.375, -0.125}, {0.125, -0.375}, {0.375, 0.125}, {-0.125, 0.375}};
  std::vector<Vec3> rays_;         // unit ray through each pixel's centre in the camera frame
  std::vector<Vec3> sample_rays_;  // kSamples unit rays per pixel
  std::vector<float> radiance_;
  std::vector<float> scratch_;
};

}  // namespace cleanslam::sim_hal::sim
