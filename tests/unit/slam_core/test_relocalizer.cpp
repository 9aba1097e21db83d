#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "cleanslam/slam_core/camera_model.hpp"
#include "cleanslam/slam_core/frontend/harris.hpp"
#include "cleanslam/slam_core/frontend/patch.hpp"
#include "cleanslam/slam_core/geometry.hpp"
#include "cleanslam/slam_core/relocalizer.hpp"
#include "frontend_synthetic.hpp"

// Relocalizer: an earlier map's landmarks, seen in a frame from a pose far from the filter's, are
// found by appearance and the planar pose from pairs of them.
namespace cs = cleanslam::slam_core;
namespace fe = cleanslam::slam_core::frontend;
namespace hal = cleanslam::hal;

namespace {

struct Scene {
  hal::Calibration calibration;
  cs::CameraModel camera{calibration.camera};
  cleanslam::test::GrayImage image = cleanslam::test::render(cleanslam::test::Warp{});
  fe::HarrisDetector detector;
  cs::Vector6d truth = cs::Vector6d::Zero();
  std::vector<int> slots;
  std::vector<Eigen::Vector3d> landmarks;
  std::vector<fe::LandmarkPatch> patches;
  std::vector<Eigen::Vector2d> pixels;  // in the frame

  // Landmarks on the frame's corners at depths from 2 m to 4 m, seen from `truth`. With
  // `closer` != 1 each was first seen from 1 / closer times its distance (its patch is taken from
  // the scene magnified by `closer`, its anchor is the camera then).
  // A landmark at pixel (x, y) of the frame, its patch from `first` (the scene magnified by
  // `closer`), at a depth from 2 m to 4 m.
  void add_landmark(double x, double y, double closer, const cleanslam::test::Warp& zoom,
                    const cleanslam::test::GrayImage& first, const Eigen::Matrix3d& R) {
    Eigen::Vector2d n;
    fe::LandmarkPatch patch;
    double u = 0.0;
    double v = 0.0;
    zoom.apply(x, y, u, v);
    if (!camera.undistort(x, y, n) || !fe::capture_patch(first.view(), u, v, 3.0 / closer, patch)) {
      return;
    }
    const double depth = 2.0 + 0.1 * static_cast<double>(slots.size() % 21);
    const Eigen::Vector3d landmark = truth.head<3>() + R * cs::CameraModel::ray(n) * depth;
    if (closer != 1.0) {
      const Eigen::Vector3d anchor = landmark - (landmark - truth.head<3>()) / closer;
      patch.anchor = {anchor.x(), anchor.y(), anchor.z()};
      patch.has_anchor = true;
    }
    slots.push_back(static_cast<int>(slots.size()) * 3);
    pixels.emplace_back(x, y);
    landmarks.push_back(landmark);
    patches.push_back(patch);
  }

  explicit Scene(double closer = 1.0) {
    truth << 1.5, -0.8, 0.1, 0.0, -0.17, 0.9;
    detector.detect(image.view(), 320, 240);
    const cleanslam::test::Warp zoom{.scale = closer};
    const cleanslam::test::GrayImage first = cleanslam::test::render(zoom);
    const Eigen::Matrix3d R = cs::rotation_zyx(truth(3), truth(4), truth(5));
    for (int i = 0; i < detector.corner_count() && static_cast<int>(slots.size()) < 20; ++i) {
      const fe::Corner& c = detector.corners()[i];
      add_landmark(c.x, c.y, closer, zoom, first, R);
    }
    // Landmarks away from every corner: never candidates, but where a pose puts them in view
    // they check it.
    for (int gy = 40; gy < 240 - 30; gy += 30) {
      for (int gx = 40; gx < 320 - 30; gx += 30) {
        bool far = true;
        for (int i = 0; i < detector.corner_count(); ++i) {
          far = far && std::hypot(detector.corners()[i].x - gx, detector.corners()[i].y - gy) > 8.0;
        }
        if (far) {
          add_landmark(gx, gy, closer, zoom, first, R);
        }
      }
    }
  }

  // The search from a filter pose off by 1.2 m and 70 degrees.
  bool relocalize(cs::Relocalizer& r, cs::Vector6d& found) const {
    cs::Vector6d wrong = truth;
    wrong(0) -= 1.0;
    wrong(1) += 0.7;
    wrong(5) -= 1.2;
    r.begin(image.view(), detector.corners(), detector.corner_count(), wrong);
    for (std::size_t i = 0; i < slots.size(); ++i) {
      r.add_landmark(slots[i], landmarks[i], patches[i]);
    }
    int steps = 0;
    while (!r.search_step()) {
      ++steps;
    }
    EXPECT_GT(steps, 1);  // bounded parts
    return r.found(found);
  }
};

}  // namespace

TEST(Relocalizer, FindsThePlanarPoseOfAFrameSeeingTheEarlierMap) {
  const Scene scene;
  ASSERT_GE(scene.slots.size(), 12U);
  cs::Relocalizer r(scene.camera);
  cs::Vector6d found;
  ASSERT_TRUE(scene.relocalize(r, found));
  EXPECT_GE(r.inliers(), 10);
  EXPECT_NEAR(found(0), scene.truth(0), 0.05);
  EXPECT_NEAR(found(1), scene.truth(1), 0.05);
  EXPECT_NEAR(cs::wrap_angle(found(5) - scene.truth(5)), 0.0, 0.02);
  // Height, roll and pitch are the filter's.
  EXPECT_EQ(found(2), scene.truth(2));
  EXPECT_EQ(found(4), scene.truth(4));
}

// First sightings from more than three times farther (patches a third the size): at scales about
// 1 hardly any match; at the scale each corner's elevation implies (the anchor's distance over
// the corner's) most do.
TEST(Relocalizer, FindsLandmarksFirstSeenFromMuchFarther) {
  const Scene scene(0.3);
  ASSERT_GE(scene.slots.size(), 12U);
  cs::Relocalizer r(scene.camera);
  cs::Vector6d found;
  ASSERT_TRUE(scene.relocalize(r, found));
  EXPECT_GE(r.inliers(), 15);
  EXPECT_NEAR(found(0), scene.truth(0), 0.05);
  EXPECT_NEAR(found(1), scene.truth(1), 0.05);
  EXPECT_NEAR(cs::wrap_angle(found(5) - scene.truth(5)), 0.0, 0.02);
}

// The first eight landmarks look as they should and lie where they should; the others lie where
// they should but their patches are of another texture: the pose the eight support puts the
// others in view, where their patches do not match, so it is not taken.
TEST(Relocalizer, APoseWhoseOtherLandmarksDoNotLookAsMappedIsNotTaken) {
  Scene scene;
  ASSERT_GE(scene.slots.size(), 16U);
  const cleanslam::test::GrayImage other = cleanslam::test::render(
      cleanslam::test::Warp{}, 320, 240, 1.0, 0.0, cleanslam::test::TextureOptions{.seed = 5});
  for (std::size_t i = 8; i < scene.slots.size(); ++i) {
    ASSERT_TRUE(fe::capture_patch(other.view(), scene.pixels[i].x(), scene.pixels[i].y(), 3.0,
                                  scene.patches[i]));
  }
  cs::RelocalizerConfig config;
  config.min_inliers = 6;
  cs::Relocalizer r(scene.camera, config);
  cs::Vector6d found;
  EXPECT_FALSE(scene.relocalize(r, found));
  EXPECT_GE(r.inliers(), 6);  // enough without the check
  EXPECT_GE(r.checked(), 8);
  EXPECT_LT(r.confirmed(), r.checked() / 5);
  // With the patches as mapped the pose is taken, and the other landmarks confirm it.
  const Scene intact;
  cs::Relocalizer r2(intact.camera, config);
  EXPECT_TRUE(intact.relocalize(r2, found));
  EXPECT_GE(r2.checked(), 8);
  EXPECT_GT(r2.confirmed(), r2.checked() / 2);
}

TEST(Relocalizer, AMapThatDoesNotFitTheViewIsNotTakenForIt) {
  Scene scene;
  // The same appearances, but each landmark somewhere else.
  for (std::size_t i = 0; i < scene.landmarks.size(); ++i) {
    const double a = 2.4 * static_cast<double>(i);
    scene.landmarks[i] += Eigen::Vector3d(1.5 * std::cos(a), 1.5 * std::sin(a), 0.0);
  }
  cs::Relocalizer r(scene.camera);
  cs::Vector6d found;
  EXPECT_FALSE(scene.relocalize(r, found));
  EXPECT_GT(r.candidate_count(), 0);
}
