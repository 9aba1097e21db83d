#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "cleanslam/sim_hal/sim/camera_effects.hpp"
#include "cleanslam/sim_hal/sim/frame_exposure.hpp"
#include "cleanslam/sim_hal/sim/renderer.hpp"
#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"
#include "cleanslam/sim_hal/sim/trajectory.hpp"
#include "sim_test_files.hpp"

using namespace cleanslam;
namespace sim = cleanslam::sim_hal::sim;
using cleanslam::sim_test::camera_at;
using cleanslam::sim_test::scenario;

namespace {

// A noise-free, blur-free camera in the default room, with `extra` on top.
sim::Scenario clean_room(std::vector<std::string> extra = {}) {
  extra.insert(extra.begin(), {"camera.image_noise=0", "camera.blur=0", "camera.tilt_deg=0"});
  return scenario("default-room", extra);
}

readers::GrayImage render(const sim::Scenario& sc, const std::vector<sim::Pose3>& poses,
                          std::uint64_t noise_seed = 1, double exposure = 1.0) {
  sim::Renderer r(sc);
  sim::Random rng(noise_seed, 5);
  readers::GrayImage img;
  r.render(poses, exposure, rng, img);
  return img;
}

double at(const readers::GrayImage& img, int x, int y) {
  return img.at(x, y);
}

// `img` averaged over horizontal shifts spread evenly over a width of `width` px (a box filter,
// linear interpolation between pixels).
std::vector<double> box_x(const readers::GrayImage& img, double width) {
  std::vector<double> out(img.pixels.size(), 0.0);
  constexpr int kShifts = 32;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      double sum = 0.0;
      for (int j = 0; j < kShifts; ++j) {
        const double xs = x + ((j + 0.5) / kShifts - 0.5) * width;
        const int x0 = std::clamp(static_cast<int>(std::floor(xs)), 0, img.width - 2);
        const double f = std::clamp(xs - x0, 0.0, 1.0);
        sum += (1.0 - f) * at(img, x0, y) + f * at(img, x0 + 1, y);
      }
      out[static_cast<std::size_t>(y * img.width + x)] = sum / kShifts;
    }
  }
  return out;
}

double rms_central(const readers::GrayImage& a, const std::vector<double>& b) {
  double s = 0.0;
  int n = 0;
  for (int y = 90; y < 150; ++y) {
    for (int x = 60; x < 260; ++x) {
      const double d = at(a, x, y) - b[static_cast<std::size_t>(y * a.width + x)];
      s += d * d;
      ++n;
    }
  }
  return std::sqrt(s / n);
}

}  // namespace

TEST(CameraEffects, MotionBlurIsABoxAsLongAsTheImageMotionDuringTheExposure) {
  // A pure yaw turn during the exposure moves the centre of the image sideways by fx * angle:
  // the blurred image is the sharp one averaged over that length, not half or twice as long.
  const auto sc = clean_room();
  const double x = 1.5, y = 2.5, yaw = 0.0;
  const auto sharp = render(sc, {camera_at(sc, x, y, yaw)});
  for (const double length_px : {4.0, 8.0}) {
    const double sweep = length_px / sc.camera.fx;
    std::vector<sim::Pose3> poses;
    constexpr int kPoses = 16;
    for (int i = 0; i < kPoses; ++i) {
      poses.push_back(camera_at(sc, x, y, yaw + sweep * ((i + 0.5) / kPoses - 0.5)));
    }
    const auto blurred = render(sc, poses);
    const double right = rms_central(blurred, box_x(sharp, length_px));
    const double none = rms_central(blurred, box_x(sharp, 0.0));
    const double half = rms_central(blurred, box_x(sharp, 0.5 * length_px));
    const double twice = rms_central(blurred, box_x(sharp, 2.0 * length_px));
    EXPECT_LT(right, 0.3 * none) << length_px;
    EXPECT_LT(right, 0.6 * half) << length_px;
    EXPECT_LT(right, 0.6 * twice) << length_px;
  }
}

TEST(CameraEffects, FramesIntegrateTheTurnDuringTheExposureTime) {
  // The simulator's frame exposure on a robot turning in place at 0.9 rad/s: a 30 ms exposure
  // smears the centre of the image over 280 px * 0.9 rad/s * 0.03 s = 7.6 px.
  const std::vector<std::string> steady = {"camera.exposure_walk=0",
                                           "camera.exposure_jump_probability=0"};
  auto with = [&](std::vector<std::string> extra) {
    extra.insert(extra.end(), steady.begin(), steady.end());
    return clean_room(extra);
  };
  const auto sharp_sc = with({});
  const auto blur_sc = with({"camera.exposure_time_s=0.03", "camera.exposure_samples=16"});
  const sim::Trajectory turning({{4.0, 0.0, 0.9, false, {}}}, {1.5, 2.5, -1.8}, 0.235);
  auto frame = [&](const sim::Scenario& sc) {
    sim::Renderer renderer(sc);
    sim::FrameExposure exposure(sc.camera, sim::body_to_camera(sc.camera));
    sim::Random rng(3, 5);
    readers::GrayImage img;
    exposure.render(renderer, turning, 2.0, rng, img);
    return img;
  };
  const auto sharp = frame(sharp_sc);
  const auto blurred = frame(blur_sc);
  const double length_px = 280.0 * 0.9 * 0.03;
  const double right = rms_central(blurred, box_x(sharp, length_px));
  EXPECT_LT(right, 0.3 * rms_central(blurred, box_x(sharp, 0.0)));
  EXPECT_LT(right, 0.6 * rms_central(blurred, box_x(sharp, 0.5 * length_px)));
  EXPECT_LT(right, 0.6 * rms_central(blurred, box_x(sharp, 2.0 * length_px)));
}

TEST(CameraEffects, FramesAutoExposeTowardsTheTarget) {
  // Standing still in front of a wall with the light at half its nominal level: the auto
  // exposure raises the gain in whole steps until the mean gray level is within half a step
  // of the target.
  const auto sc = clean_room({"camera.exposure_walk=0", "camera.exposure_jump_probability=0",
                              "camera.auto_exposure=true", "camera.auto_exposure_target=150",
                              "camera.auto_exposure_step_ev=0.25"});
  const sim::Trajectory still({{10.0, 0.0, 0.0, false, {}}}, {3.0, 2.5, 0.0}, 0.235);
  sim::Renderer renderer(sc);
  sim::FrameExposure exposure(sc.camera, sim::body_to_camera(sc.camera));
  sim::Random rng(3, 5);
  readers::GrayImage img;
  auto mean = [&] {
    double s = 0.0;
    for (const auto p : img.pixels) {
      s += p;
    }
    return s / static_cast<double>(img.pixels.size());
  };
  exposure.render(renderer, still, 0.0, rng, img);
  const double first = mean();
  for (int k = 1; k < 12; ++k) {
    exposure.render(renderer, still, 0.5 * k, rng, img);
  }
  EXPECT_GT(exposure.max_gain(), 1.0);
  EXPECT_NEAR(std::log2(mean() / 150.0), 0.0, 0.125 + 0.02) << "first frame " << first;
  const double steps = std::log2(exposure.max_gain()) / 0.25;
  EXPECT_NEAR(steps, std::round(steps), 1e-9);
}

TEST(CameraEffects, VignettingFollowsTheCos4Profile) {
  const auto plain = clean_room();
  const auto vignetted = clean_room({"camera.vignetting=0.6"});
  const auto pose = camera_at(plain, 2.0, 2.5, 0.3);
  const auto a = render(plain, {pose});
  const auto b = render(vignetted, {pose});
  for (const auto& [x, y] :
       {std::pair{160, 120}, {20, 20}, {300, 20}, {20, 220}, {300, 220}, {160, 20}, {40, 120}}) {
    double sa = 0.0;
    double sb = 0.0;
    for (int dy = -3; dy <= 3; ++dy) {
      for (int dx = -3; dx <= 3; ++dx) {
        sa += at(a, x + dx, y + dy);
        sb += at(b, x + dx, y + dy);
      }
    }
    const double nx = (x - 159.5) / 280.0, ny = (y - 119.5) / 280.0;
    const double expected = 1.0 / std::pow(1.0 + 0.6 * (nx * nx + ny * ny), 2.0);
    EXPECT_NEAR(sb / sa, expected, 0.01) << x << "," << y;
  }
  EXPECT_NEAR(sim::vignetting_factor(vignetted.camera, 0.0, 0.0),
              1.0 / std::pow(1.0 + 0.6 * (159.5 * 159.5 + 119.5 * 119.5) / (280.0 * 280.0), 2.0),
              1e-12);
}

TEST(CameraEffects, NoiseVarianceGrowsWithTheSignal) {
  // Read noise 1.5 gray levels and shot noise 0.4 gray levels per electron: the variance of a
  // pixel is 1.5^2 + 0.4 * signal (+1/12 of rounding). Two renders differing only in the noise
  // draw: half the variance of their difference, per signal band.
  const auto sc = clean_room({"camera.image_noise=1.5", "camera.shot_noise_gain=0.4"});
  const auto pose = camera_at(sc, 2.0, 2.5, 0.3);
  const auto a = render(sc, {pose}, 1, 1.3);
  const auto b = render(sc, {pose}, 2, 1.3);
  std::vector<double> sum(6, 0.0), sum2(6, 0.0), n(6, 0.0);
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const double mean = 0.5 * (a.pixels[i] + b.pixels[i]);
    const auto band = static_cast<std::size_t>(mean / 40.0);
    if (band >= 6 || a.pixels[i] == 255 || b.pixels[i] == 255) {
      continue;
    }
    const double d = static_cast<double>(a.pixels[i]) - b.pixels[i];
    sum[band] += mean;
    sum2[band] += d * d;
    n[band] += 1.0;
  }
  int bands = 0;
  for (std::size_t k = 0; k < 6; ++k) {
    if (n[k] < 2000) {
      continue;
    }
    ++bands;
    const double signal = sum[k] / n[k];
    const double variance = 0.5 * sum2[k] / n[k];
    const double expected = 1.5 * 1.5 + 0.4 * signal + 1.0 / 12.0;
    EXPECT_NEAR(variance, expected, 0.1 * expected) << "signal " << signal;
  }
  EXPECT_GE(bands, 2);
  EXPECT_DOUBLE_EQ(sim::sensor_noise_sigma(2.0, 0.5, 32.0, 1.0), std::sqrt(4.0 + 16.0));
  // At gain 4 the same signal came from a quarter of the light: 4 times the read noise, twice
  // the shot noise's standard deviation.
  EXPECT_DOUBLE_EQ(sim::sensor_noise_sigma(2.0, 0.5, 32.0, 4.0), std::sqrt(64.0 + 64.0));
}

TEST(CameraEffects, AutoExposureStepsTheGainTowardsTheTarget) {
  sim::AutoExposure ae(110.0, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(ae.gain(), 1.0);
  double light = 30.0;  // mean gray level at gain 1
  int last = 0;
  for (int frame = 0; frame < 40; ++frame) {
    if (frame == 20) {
      light *= 2.0;
    }
    ae.update(light * ae.gain());
    EXPECT_LE(std::abs(ae.steps() - last), 2);
    EXPECT_NEAR(ae.gain(), std::exp2(ae.steps() / 3.0), 1e-12);
    last = ae.steps();
    if (frame == 19 || frame == 39) {
      // Settled within half a step of the target.
      EXPECT_NEAR(std::log2(light * ae.gain() / 110.0), 0.0, 1.0 / 6.0 + 1e-9) << frame;
    }
  }
  // Twice the light: one stop, three steps down.
  sim::AutoExposure dark(110.0, 1.0 / 3.0);
  for (int i = 0; i < 20; ++i) {
    dark.update(30.0 * dark.gain());
  }
  EXPECT_EQ(last, dark.steps() - 3);
}

TEST(CameraEffects, DistortionIsTheCalibrationsRadialTangentialModel) {
  // The simulator's projection is hal::CameraCalibration's k1 k2 p1 p2 model, as sensors.yaml
  // states it, at a few points across the image of the realistic camera.
  const auto sc = scenario("realistic-camera", {});
  const auto& c = sc.camera;
  const double k1 = c.distortion[0], k2 = c.distortion[1], p1 = c.distortion[2],
               p2 = c.distortion[3];
  EXPECT_NE(k1, 0.0);
  for (const auto& [x, y] : {std::pair{0.0, 0.0}, {0.5, 0.4}, {-0.55, 0.3}, {0.2, -0.4}}) {
    const double r2 = x * x + y * y;
    const double radial = 1.0 + k1 * r2 + k2 * r2 * r2;
    const double xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
    const double yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
    double u = 0.0;
    double v = 0.0;
    ASSERT_TRUE(sim::project(c, {2.0 * x, 2.0 * y, 2.0}, u, v));
    EXPECT_NEAR(u, c.fx * xd + c.cx, 1e-9);
    EXPECT_NEAR(v, c.fy * yd + c.cy, 1e-9);
  }
  const auto cal = sim::calibration_of(sc);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(cal.camera.distortion[i], c.distortion[i]);
  }
}

TEST(CameraEffects, RealisticCameraScenarioTurnsFastAtALowFrameRate) {
  const auto sc = scenario("realistic-camera", {});
  EXPECT_GE(sc.path.turn_rate, 40.0 * std::numbers::pi / 180.0);
  EXPECT_GE(sc.camera.rate_hz, 1.0);
  EXPECT_LE(sc.camera.rate_hz, 2.0);
  EXPECT_EQ(sc.camera.mode, "images");
  EXPECT_EQ(sc.camera.textures, "photos");
  EXPECT_GT(sc.camera.exposure_time_s, 0.0);
  EXPECT_GT(sc.camera.shot_noise_gain, 0.0);
  EXPECT_GT(sc.camera.vignetting, 0.0);
  EXPECT_TRUE(sc.camera.auto_exposure);
}

TEST(CameraEffects, RendersTheSameBytesForTheSameSeed) {
  const auto sc = scenario("realistic-camera", {});
  const auto pose = camera_at(sc, 2.0, 2.5, 0.3);
  const std::vector<sim::Pose3> poses = {pose, camera_at(sc, 2.0, 2.5, 0.31)};
  const auto a = render(sc, poses, 7);
  const auto b = render(sc, poses, 7);
  const auto c = render(sc, poses, 8);
  EXPECT_EQ(a.pixels, b.pixels);
  EXPECT_NE(a.pixels, c.pixels);
}

TEST(CameraEffects, PhotographsOrProceduralTexturesSayingWhy) {
  const auto missing = scenario("realistic-camera", {"camera.photo_dir=/nonexistent/photos"});
  sim::Renderer fallback(missing);
  EXPECT_FALSE(fallback.photos_in_use());
  EXPECT_NE(fallback.textures_note().find("/nonexistent/photos/brick.png"), std::string::npos);
  EXPECT_NE(fallback.textures_note().find("python3-skimage"), std::string::npos);
  const auto sc = scenario("realistic-camera", {});
  sim::Renderer photos(sc);
  if (!photos.photos_in_use()) {
    GTEST_SKIP() << photos.textures_note();
  }
  // The photographs change the image: same pose and noise, different textures.
  const auto pose = camera_at(sc, 2.0, 2.5, 0.3);
  EXPECT_NE(render(sc, {pose}).pixels, render(missing, {pose}).pixels);
}
