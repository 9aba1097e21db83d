#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/dataset_source.hpp"
#include "cleanslam/sim_hal/sim/renderer.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"
#include "sim_test_files.hpp"

namespace fs = std::filesystem;
using namespace cleanslam;
namespace sim = cleanslam::sim_hal::sim;
using cleanslam::sim_test::camera_at;

namespace {

sim::Scenario room(const std::vector<std::string>& extra = {}) {
  auto sc = sim::load_scenario("default-room", extra);
  EXPECT_TRUE(sc.ok()) << sc.error();
  return *sc;
}

// Camera of the scenario on a robot at (x, y) with heading yaw.
}  // namespace

TEST(Renderer, FloorWallBoundaryIsWhereTheGeometrySaysIt) {
  auto sc = room({"camera.tilt_deg=0", "world.furniture=[]"});
  sim::Renderer r(sc);
  // Facing the east wall (x = 6) from x = 3: the camera is 2.9 m from it, 0.1 m up, so the
  // wall's foot is imaged 280 * 0.1 / 2.9 = 9.66 px below the centre row.
  const auto wc = camera_at(sc, 3.0, 2.5, 0.0);
  const double foot = 119.5 + 280.0 * 0.10 / 2.9;
  const int x = 160;
  EXPECT_EQ(r.surface_at(wc, x, static_cast<int>(std::floor(foot)) - 1), 5);  // east wall
  EXPECT_EQ(r.surface_at(wc, x, static_cast<int>(std::ceil(foot)) + 1), 0);   // floor
  // The ceiling (2.5 m) is seen above 119.5 - 280 * 2.4 / 2.9 = -112: not at all.
  EXPECT_EQ(r.surface_at(wc, x, 0), 5);
  // Looking north along y from the middle the left image edge sees the west wall (x = 0).
  const auto north = camera_at(sc, 0.5, 1.0, std::numbers::pi / 2);
  EXPECT_EQ(r.surface_at(north, 0, 100), 4);
}

TEST(Renderer, FurnitureHidesTheWall) {
  auto sc =
      room({"camera.tilt_deg=0", "world.furniture=[{min: [4.0, 2.0, 0.0], max: [4.5, 3.0, 1.0]}]"});
  sim::Renderer r(sc);
  const auto wc = camera_at(sc, 2.0, 2.5, 0.0);
  EXPECT_EQ(r.surface_at(wc, 160, 119), 6);  // the box, 1.9 m ahead
  const auto beside = camera_at(sc, 2.0, 1.0, 0.0);
  EXPECT_EQ(r.surface_at(beside, 160, 119), 5);  // past it: the wall
}

TEST(Renderer, RendersTexturedDeterministicImages) {
  auto sc = room();
  sim::Renderer r1(sc), r2(sc);
  sim::Random a(3), b(3);
  readers::GrayImage i1, i2;
  const auto wc = camera_at(sc, 1.0, 1.0, 0.6);
  r1.render(wc, 1.0, a, i1);
  r2.render(wc, 1.0, b, i2);
  ASSERT_EQ(i1.width, 320);
  ASSERT_EQ(i1.height, 240);
  EXPECT_EQ(i1.pixels, i2.pixels);
  // Texture: a wide spread of gray levels, not saturated.
  int lo = 255, hi = 0;
  double mean = 0.0;
  for (auto p : i1.pixels) {
    lo = std::min<int>(lo, p);
    hi = std::max<int>(hi, p);
    mean += p;
  }
  mean /= static_cast<double>(i1.pixels.size());
  EXPECT_GT(hi - lo, 100);
  EXPECT_GT(mean, 40.0);
  EXPECT_LT(mean, 200.0);
  // Brighter exposure, brighter image.
  readers::GrayImage i3;
  sim::Random c(3);
  r1.render(wc, 1.3, c, i3);
  double mean3 = 0.0;
  for (auto p : i3.pixels) {
    mean3 += p;
  }
  EXPECT_GT(mean3 / static_cast<double>(i3.pixels.size()), mean * 1.15);
}

TEST(Renderer, ImagesModeWritesAReadableDataset) {
  const fs::path dir =
      fs::temp_directory_path() / ("cleanslam_render_dataset_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  auto sc = room({"camera.mode=both", "duration_s=5", "camera.image_format=pgm"});
  ASSERT_TRUE(sim::simulate(sc, dir.string()).ok());
  auto src = readers::DatasetSource::open(dir.string());
  ASSERT_TRUE(src.ok()) << src.error();
  hal::SensorEvent ev;
  int frames = 0, with_both = 0;
  while (src->read(ev)) {
    if (ev.kind != hal::SensorEvent::Kind::kFrame) {
      continue;
    }
    ++frames;
    ASSERT_TRUE(ev.frame.has_image());
    EXPECT_EQ(ev.frame.image.width, 320);
    with_both += ev.frame.has_features() ? 1 : 0;
  }
  EXPECT_EQ(frames, 10);
  EXPECT_GT(with_both, 5);
  EXPECT_EQ(src->image_errors(), 0);
  fs::remove_all(dir);
}

TEST(Renderer, PointAtASubPixelProjectsBackToIt) {
  // With lens distortion, the ray through (u, v) and the projection of the point it hits agree
  // to a small fraction of a pixel: the ray caster and the camera model share the pixel-centre
  // convention (integer coordinates at pixel centres, as cx, cy).
  auto sc = room({"camera.distortion=[-0.2, 0.05, 0.001, -0.001]"});
  sim::Renderer r(sc);
  const auto wc = camera_at(sc, 2.0, 2.0, 0.7);
  for (const auto& [u, v] :
       {std::pair{10.25, 12.5}, {159.5, 119.5}, {301.75, 40.125}, {200.3, 230.9}}) {
    const auto hit = r.point_at(wc, u, v);
    ASSERT_GE(hit.surface, 0);
    EXPECT_NEAR(sim::norm(hit.point - wc.position), hit.distance, 1e-9);
    double pu = 0.0;
    double pv = 0.0;
    ASSERT_TRUE(sim::project(sc.camera, wc.apply_inverse(hit.point), pu, pv));
    EXPECT_NEAR(pu, u, 1e-6);
    EXPECT_NEAR(pv, v, 1e-6);
  }
}

TEST(Renderer, PixelsAverageTheirAreaAcrossAnEdge) {
  // The wall's foot crosses the column part-way through a pixel: that pixel is a blend of wall
  // and floor, not one or the other (four samples per pixel), so edges move smoothly.
  auto sc =
      room({"camera.tilt_deg=0", "world.furniture=[]", "camera.image_noise=0", "camera.blur=0"});
  sim::Renderer r(sc);
  sim::Random rng(1, 1);
  cleanslam::readers::GrayImage img;
  int blended = 0;
  // Seen from several distances the foot falls at different sub-pixel rows.
  for (const double x : {2.6, 2.8, 3.0, 3.2, 3.4}) {
    const auto wc = camera_at(sc, x, 2.5, 0.0);
    r.render(wc, 1.0, rng, img);
    const double foot = 119.5 + 280.0 * 0.10 / (6.0 - x - 0.1);
    const int row = static_cast<int>(std::lround(foot));
    const int above = img.pixels[static_cast<std::size_t>((row - 2) * 320 + 160)];
    const int at = img.pixels[static_cast<std::size_t>(row * 320 + 160)];
    const int below = img.pixels[static_cast<std::size_t>((row + 2) * 320 + 160)];
    if (std::abs(above - below) > 8 && at > std::min(above, below) + 2 &&
        at < std::max(above, below) - 2) {
      ++blended;
    }
  }
  EXPECT_GE(blended, 2);
}
