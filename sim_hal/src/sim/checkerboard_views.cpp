#include "cleanslam/sim_hal/sim/checkerboard_views.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "cleanslam/sim_hal/sim/renderer.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"

namespace cleanslam::sim_hal::sim {
namespace {

constexpr double kRadPerDegree = std::numbers::pi / 180.0;
constexpr double kBlack = 25.0;
constexpr double kWhite = 225.0;
constexpr double kBackground = 110.0;
constexpr int kGrid = 4;  // kGrid x kGrid rays per pixel

// Whether the board with its border, seen from `cb`, lies wholly in the image (`margin` px in).
bool board_in_view(const Scenario& sc, const Pose3& cb, double margin) {
  const auto& b = sc.checkerboard;
  const double s = b.square_m;
  for (const double x : {-2.0 * s, (b.cols + 1) * s}) {
    for (const double y : {-2.0 * s, (b.rows + 1) * s}) {
      double u = 0.0, v = 0.0;
      if (!project(sc.camera, cb.apply(Vec3{x, y, 0.0}), u, v)) {
        return false;
      }
      if (u < margin || v < margin || u > sc.camera.width - 1.0 - margin ||
          v > sc.camera.height - 1.0 - margin) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace

Pose3 checkerboard_pose(const Scenario& sc, int index, Random& rng) {
  const auto& b = sc.checkerboard;
  const auto& c = sc.camera;
  const Vec3 centre{0.5 * (b.cols - 1) * b.square_m, 0.5 * (b.rows - 1) * b.square_m, 0.0};
  const Mat3 r = rot_x(rng.uniform(-35.0, 35.0) * kRadPerDegree) *
                 rot_y(rng.uniform(-35.0, 35.0) * kRadPerDegree) *
                 rot_z(rng.uniform(-15.0, 15.0) * kRadPerDegree);
  // The board's centre aims at a cell of a 3 x 3 grid over the image, in turn.
  double u = c.width * (0.25 + 0.25 * (index % 3)) + rng.uniform(-0.05, 0.05) * c.width;
  double v = c.height * (0.25 + 0.25 * ((index / 3) % 3)) + rng.uniform(-0.05, 0.05) * c.height;
  double depth = rng.uniform(0.4, 0.8) * b.square_m * (b.cols + 3) / 0.36 * c.fx / 280.0;
  Pose3 cb;
  for (int attempt = 0; attempt < 60; ++attempt) {
    const Vec3 ray = pixel_ray(c, u, v);
    cb = Pose3{r, (depth / ray.z) * ray - r * centre};
    if (board_in_view(sc, cb, 4.0)) {
      break;
    }
    // Towards the image's centre, then farther away.
    u += 0.2 * (c.cx - u);
    v += 0.2 * (c.cy - v);
    if (attempt % 10 == 9) {
      depth *= 1.15;
    }
  }
  return cb;
}

Pose3 checkerboard_on_floor_pose(const Scenario& sc) {
  const auto& f = *sc.checkerboard.on_floor;
  const Pose3 body_board{rot_z(f[2] * kRadPerDegree), Vec3{f[0], f[1], 0.0}};
  const Pose3 body_camera = body_to_camera(sc.camera);
  const Mat3 camera_body = transpose(body_camera.rotation);
  return compose(Pose3{camera_body, -1.0 * (camera_body * body_camera.position)}, body_board);
}

CheckerboardRenderer::CheckerboardRenderer(const Scenario& sc)
    : camera_(sc.camera), board_(sc.checkerboard) {
  rays_.reserve(static_cast<std::size_t>(camera_.width) * static_cast<std::size_t>(camera_.height) *
                kGrid * kGrid);
  for (int y = 0; y < camera_.height; ++y) {
    for (int x = 0; x < camera_.width; ++x) {
      for (int i = 0; i < kGrid; ++i) {
        for (int j = 0; j < kGrid; ++j) {
          rays_.push_back(
              pixel_ray(camera_, x + (i + 0.5) / kGrid - 0.5, y + (j + 0.5) / kGrid - 0.5));
        }
      }
    }
  }
}

void CheckerboardRenderer::render(const Pose3& cb, Random& rng, readers::GrayImage& out) const {
  const auto& b = board_;
  const double s = b.square_m;
  const Vec3 normal = cb.rotation * Vec3{0.0, 0.0, 1.0};
  const double plane = dot(normal, cb.position);
  auto radiance = [&](Vec3 ray) {
    const double along = dot(normal, ray);
    if (std::abs(along) < 1e-12 || plane / along <= 0.0) {
      return kBackground;
    }
    const Vec3 q = cb.apply_inverse((plane / along) * ray);
    if (q.x < -2.0 * s || q.y < -2.0 * s || q.x > (b.cols + 1) * s || q.y > (b.rows + 1) * s) {
      return kBackground;
    }
    if (q.x < -s || q.y < -s || q.x > b.cols * s || q.y > b.rows * s) {
      return kWhite;
    }
    const auto i = static_cast<long>(std::floor(q.x / s));
    const auto j = static_cast<long>(std::floor(q.y / s));
    return (i + j) % 2 == 0 ? kBlack : kWhite;
  };
  out = readers::GrayImage(camera_.width, camera_.height);
  std::size_t r = 0;
  for (int y = 0; y < camera_.height; ++y) {
    for (int x = 0; x < camera_.width; ++x) {
      double sum = 0.0;
      for (int k = 0; k < kGrid * kGrid; ++k) {
        sum += radiance(rays_[r++]);
      }
      const double g = sum / (kGrid * kGrid) + rng.gaussian(camera_.image_noise);
      out.at(x, y) = static_cast<std::uint8_t>(std::clamp(std::lround(g), 0L, 255L));
    }
  }
}

}  // namespace cleanslam::sim_hal::sim
