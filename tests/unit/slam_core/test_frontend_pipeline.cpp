#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cleanslam/slam_core/frontend/frame_pipeline.hpp"
#include "frontend_fake_estimator.hpp"
#include "frontend_synthetic.hpp"

namespace fe = cleanslam::slam_core::frontend;
using cleanslam::test::FakeEstimator;
using cleanslam::test::GrayImage;
using cleanslam::test::render;
using cleanslam::test::Warp;

namespace {

Warp forward(int k) {
  Warp w;
  w.scale = std::pow(1.06, k);
  w.shift_x = 1.5 * k;
  w.shift_y = -0.7 * k;
  return w;
}

Warp with_error(Warp w, double ex, double ey) {
  w.shift_x += ex;
  w.shift_y += ey;
  return w;
}

// Largest distance between a matched track and the truth (the landmark's texture point through
// the true warp).
double max_track_error(const fe::FramePipeline& pipe, const FakeEstimator& est, const Warp& truth) {
  double worst = 0.0;
  for (int i = 0; i < pipe.track_count(); ++i) {
    const fe::TrackRecord& t = pipe.tracks()[i];
    if (!t.result.found) {
      continue;
    }
    double tx = 0.0;
    double ty = 0.0;
    est.true_texture_point(t.slot, tx, ty);
    double u = 0.0;
    double v = 0.0;
    truth.apply(tx, ty, u, v);
    worst = std::max(worst, std::hypot(t.result.u_px - u, t.result.v_px - v));
  }
  return worst;
}

// The reference view with its left half covered by a flat board.
GrayImage covered_left_half() {
  GrayImage covered = render(Warp{});
  for (int y = 0; y < 240; ++y) {
    for (int x = 0; x < 160; ++x) {
      covered.at(x, y) = 90;
    }
  }
  return covered;
}

}  // namespace

TEST(FrontendPipeline, FirstFrameInitializesTheTargetNumberOfLandmarks) {
  fe::FramePipeline pipe;
  FakeEstimator est;
  const GrayImage img = render(Warp{});
  ASSERT_EQ(pipe.begin_frame(img.view()), fe::ImageCheck::kOk);
  const fe::FrameReport& r = pipe.finish(est);
  EXPECT_GT(r.corners, 50);
  EXPECT_EQ(r.initialized, 10);
  EXPECT_EQ(est.used_count(), 10);
  EXPECT_EQ(pipe.book().active_count(), 10);
  EXPECT_FALSE(r.updated);
  // New landmarks are spread out: at least the exclusion distance apart.
  for (int i = 0; i < pipe.new_landmark_count(); ++i) {
    ASSERT_NE(pipe.patches().get(pipe.new_landmark(i).slot), nullptr);
    for (int j = 0; j < i; ++j) {
      EXPECT_GE(std::hypot(pipe.new_landmark(i).u_px - pipe.new_landmark(j).u_px,
                           pipe.new_landmark(i).v_px - pipe.new_landmark(j).v_px),
                20.0);
    }
  }
}

TEST(FrontendPipeline, KeepsTracksWhileDrivingForward) {
  fe::FramePipeline pipe;
  FakeEstimator est;
  est.belief = with_error(forward(0), 1.0, -0.5);
  est.truth = forward(0);
  const GrayImage first = render(forward(0));
  pipe.begin_frame(first.view());
  pipe.finish(est);
  ASSERT_EQ(est.used_count(), 10);
  int total_tracked = 0;
  for (int k = 1; k <= 6; ++k) {
    const Warp truth = forward(k);
    est.belief = with_error(truth, 1.0, -0.5);
    est.truth = truth;
    const GrayImage img = render(truth);
    pipe.begin_frame(img.view());
    const fe::FrameReport& r = pipe.finish(est);
    EXPECT_GE(r.in_view, 5) << "frame " << k;
    // Every landmark predicted inside the image is found (some at the border too).
    EXPECT_GE(r.tracked, r.in_view) << "frame " << k;
    EXPECT_EQ(r.inliers, r.tracked) << "frame " << k;
    EXPECT_TRUE(r.updated) << "frame " << k;
    EXPECT_EQ(est.last_fused, r.inliers);
    EXPECT_EQ(r.deleted, 0) << "frame " << k;
    EXPECT_LT(max_track_error(pipe, est, truth), 0.3) << "frame " << k;
    total_tracked += r.tracked;
  }
  // By frame 6 the image is magnified 1.42 times; the first landmarks are still tracked.
  EXPECT_GT(total_tracked, 40);
  EXPECT_EQ(est.deletions, 0);
}

TEST(FrontendPipeline, StepsDoBoundedWork) {
  fe::FramePipelineConfig cfg;
  cfg.detect_rows_per_step = 30;
  cfg.tracks_per_step = 2;
  cfg.initializations_per_step = 3;
  fe::FramePipeline pipe(cfg);
  FakeEstimator est;
  const GrayImage first = render(Warp{});
  pipe.begin_frame(first.view());
  int steps = 0;
  int last_init = 0;
  while (pipe.step(est)) {
    ++steps;
    EXPECT_LE(pipe.report().initialized - last_init, 3);
    last_init = pipe.report().initialized;
  }
  EXPECT_EQ(pipe.report().initialized, 10);
  Warp w;
  w.shift_x = 2.0;
  est.belief = w;
  const GrayImage img = render(w);
  pipe.begin_frame(img.view());
  int track_steps = 0;
  int detect_steps = 0;
  int last_tracked = 0;
  while (true) {
    const fe::FrameStage before = pipe.stage();
    const bool more = pipe.step(est);
    detect_steps += before == fe::FrameStage::kDetect ? 1 : 0;
    if (before == fe::FrameStage::kTrack) {
      ++track_steps;
      EXPECT_LE(pipe.report().tracked - last_tracked, 2);
    }
    last_tracked = pipe.report().tracked;
    if (!more) {
      break;
    }
  }
  EXPECT_EQ(pipe.report().tracked, 10);
  EXPECT_EQ(track_steps, 5);
  EXPECT_EQ(detect_steps, 8);  // rows 1..238 in pieces of 30
  EXPECT_EQ(pipe.stage(), fe::FrameStage::kDone);
  EXPECT_FALSE(pipe.step(est));
}

TEST(FrontendPipeline, LandmarksThatKeepFailingAreDeletedAndReplaced) {
  fe::FramePipeline pipe;
  FakeEstimator est;
  const GrayImage first = render(Warp{});
  // Matched often enough not to be young any more (a young landmark goes at its first miss).
  for (int k = 0; k <= pipe.book().config().min_matches_to_keep; ++k) {
    pipe.begin_frame(first.view());
    pipe.finish(est);
  }
  // From now on the left half is covered by a flat board. Landmarks whose window lies on it
  // fail; those well right of its edge stay.
  std::vector<int> covered_slots;
  std::vector<int> free_slots;
  for (int s = 0; s < cleanslam::hal::kMaxLandmarks; ++s) {
    if (est.used(s)) {
      double x = 0.0;
      double y = 0.0;
      est.texture_point(s, x, y);
      if (x < 152.0) {
        covered_slots.push_back(s);
      } else if (x > 168.0) {
        free_slots.push_back(s);
      }
    }
  }
  ASSERT_FALSE(covered_slots.empty());
  ASSERT_FALSE(free_slots.empty());
  const GrayImage covered = covered_left_half();
  // Each covered landmark fails once per frame it is searched in (more landmarks than tracks
  // can leave it unsearched in a frame: young ones come first) and goes at its third failure.
  std::vector<int> failures(covered_slots.size(), 0);
  std::vector<bool> gone(covered_slots.size(), false);
  int deleted = 0;
  for (int k = 1; k <= 8; ++k) {
    pipe.begin_frame(covered.view());
    const fe::FrameReport& r = pipe.finish(est);
    deleted += r.deleted;
    for (std::size_t i = 0; i < covered_slots.size(); ++i) {
      const int s = covered_slots[i];
      if (gone[i]) {
        continue;
      }
      bool reused = false;
      for (int j = 0; j < pipe.new_landmark_count(); ++j) {
        reused = reused || pipe.new_landmark(j).slot == s;
      }
      if (!est.used(s) || reused) {
        EXPECT_EQ(failures[i], pipe.book().config().max_consecutive_failures - 1)
            << "slot " << s << " frame " << k;
        gone[i] = true;
        continue;
      }
      const int f = pipe.book().failures(s);
      EXPECT_TRUE(f == failures[i] || f == failures[i] + 1) << "slot " << s << " frame " << k;
      failures[i] = f;
    }
    for (int s : free_slots) {
      EXPECT_TRUE(est.used(s));
      EXPECT_EQ(pipe.book().failures(s), 0);
    }
    // Every landmark taken while the board is there is on the textured half.
    for (int i = 0; i < pipe.new_landmark_count(); ++i) {
      EXPECT_GT(pipe.new_landmark(i).u_px, 160.0);
    }
  }
  for (std::size_t i = 0; i < covered_slots.size(); ++i) {
    EXPECT_TRUE(gone[i]) << "slot " << covered_slots[i];
  }
  EXPECT_GE(deleted, static_cast<int>(covered_slots.size()));
  EXPECT_EQ(est.deletions, deleted);
  EXPECT_GE(pipe.book().active_count(), 5);
}

TEST(FrontendPipeline, FeaturelessFramesGiveNoUpdateAndNoError) {
  fe::FramePipeline pipe;
  FakeEstimator est;
  const GrayImage first = render(Warp{});
  pipe.begin_frame(first.view());
  pipe.finish(est);
  const GrayImage black(320, 240, 0);
  const GrayImage white(320, 240, 255);
  const GrayImage gray(320, 240, 128);
  const GrayImage saturated = render(Warp{}, 320, 240, 1.0, 400.0);
  for (const GrayImage* img : {&black, &white, &gray, &saturated, &black, &black}) {
    ASSERT_EQ(pipe.begin_frame(img->view()), fe::ImageCheck::kOk);
    const fe::FrameReport& r = pipe.finish(est);
    EXPECT_TRUE(r.featureless);
    EXPECT_FALSE(r.updated);
    EXPECT_EQ(r.deleted, 0);
    EXPECT_EQ(r.initialized, 0);
  }
  EXPECT_EQ(est.updates, 0);
  EXPECT_EQ(est.deletions, 0);
  pipe.begin_frame(first.view());
  const fe::FrameReport& r = pipe.finish(est);
  EXPECT_EQ(r.tracked, 10);
  EXPECT_TRUE(r.updated);
}

TEST(FrontendPipeline, WrongSizeFrameIsRejectedWithAClearMessage) {
  fe::FramePipeline pipe;
  FakeEstimator est;
  const GrayImage small(160, 120, 50);
  EXPECT_EQ(pipe.begin_frame(small.view()), fe::ImageCheck::kWrongSize);
  EXPECT_EQ(pipe.stage(), fe::FrameStage::kDone);
  EXPECT_FALSE(pipe.step(est));
  char msg[128];
  EXPECT_EQ(std::string(pipe.describe(msg, sizeof(msg))),
            "image 160x120 does not match the configured 320x240");
  EXPECT_EQ(est.initializations, 0);
}

TEST(FrontendPipeline, JointlyInconsistentMatchIsNotFused) {
  fe::FramePipeline pipe;
  FakeEstimator est;
  const GrayImage first = render(Warp{});
  pipe.begin_frame(first.view());
  pipe.finish(est);
  // The estimator misplaces one landmark by 6 px: individually plausible (sigma 4.1 px), but its
  // innovation disagrees with the others' shared one.
  Warp w;
  w.shift_x = 3.0;
  w.shift_y = 1.0;
  est.belief = with_error(w, 0.5, 0.5);
  const GrayImage img = render(w);
  pipe.begin_frame(img.view());
  // Shift the fake's landmark 0 after the first stage so its prediction is off.
  int bad_slot = -1;
  for (int s = 0; s < cleanslam::hal::kMaxLandmarks && bad_slot < 0; ++s) {
    if (est.used(s)) {
      bad_slot = s;
    }
  }
  ASSERT_GE(bad_slot, 0);
  FakeEstimator::Nudge nudge{bad_slot, 6.0, 0.0};
  est.nudge(nudge);
  const fe::FrameReport& r = pipe.finish(est);
  EXPECT_EQ(r.tracked, 10);
  EXPECT_EQ(r.outliers, 1);
  EXPECT_EQ(r.inliers, 9);
  EXPECT_EQ(est.last_fused, 9);
  for (int i = 0; i < pipe.track_count(); ++i) {
    EXPECT_EQ(pipe.tracks()[i].inlier, pipe.tracks()[i].slot != bad_slot);
  }
}

TEST(FrontendPipeline, StandingStillTracksButDoesNotUpdate) {
  fe::FramePipeline pipe;
  FakeEstimator est;
  const GrayImage first = render(Warp{});
  pipe.begin_frame(first.view());
  pipe.finish(est);
  pipe.begin_frame(first.view(), false);
  const fe::FrameReport& r = pipe.finish(est);
  EXPECT_EQ(r.tracked, 10);
  EXPECT_EQ(r.inliers, 10);
  EXPECT_FALSE(r.updated);
  EXPECT_EQ(est.updates, 0);
}

TEST(FrontendPipeline, TwoLandmarksOnOnePixelKeepOnlyTheBetterMatch) {
  // Landmarks allowed next to each other (no exclusion) and a duplicate distance larger than the
  // corners' minimum distance: neighbouring landmarks count as duplicates.
  fe::FramePipelineConfig cfg;
  cfg.book.exclusion_px = 0.0;
  cfg.book.min_in_view = 16;
  cfg.book.target_in_view = 16;
  cfg.harris.min_distance_px = 3.0F;
  cfg.duplicate_px = 12.0;
  fe::FramePipeline pipe(cfg);
  FakeEstimator est;
  // Small bright squares: their four corners, 6 px apart, all become landmarks.
  GrayImage img(320, 240, 60);
  for (int cy = 60; cy < 200; cy += 60) {
    for (int cx = 60; cx < 280; cx += 70) {
      for (int y = cy; y < cy + 6; ++y) {
        for (int x = cx; x < cx + 6; ++x) {
          img.at(x, y) = 200;
        }
      }
    }
  }
  pipe.begin_frame(img.view());
  pipe.finish(est);
  ASSERT_EQ(est.used_count(), 16);
  pipe.begin_frame(img.view());
  const fe::FrameReport& r = pipe.finish(est);
  EXPECT_GT(r.duplicates, 0);
  EXPECT_EQ(r.tracked + r.duplicates, r.in_view);
  for (int i = 0; i < pipe.track_count(); ++i) {
    const fe::TrackRecord& a = pipe.tracks()[i];
    if (!a.result.found) {
      EXPECT_EQ(a.result.failure, fe::TrackFailure::kDuplicate);
      continue;
    }
    for (int j = 0; j < i; ++j) {
      const fe::TrackRecord& b = pipe.tracks()[j];
      if (b.result.found) {
        EXPECT_GE(std::hypot(a.result.u_px - b.result.u_px, a.result.v_px - b.result.v_px), 12.0);
      }
    }
  }
}

TEST(FrontendPipeline, YoungLandmarksGoAtTheirFirstMiss) {
  fe::FramePipeline pipe;
  FakeEstimator est;
  const GrayImage first = render(Warp{});
  pipe.begin_frame(first.view());
  pipe.finish(est);
  ASSERT_EQ(est.used_count(), 10);
  std::vector<int> covered_slots;
  for (int s = 0; s < cleanslam::hal::kMaxLandmarks; ++s) {
    double x = 0.0;
    double y = 0.0;
    est.texture_point(s, x, y);
    if (est.used(s) && x < 152.0) {
      covered_slots.push_back(s);
      EXPECT_TRUE(pipe.book().young(s));
    }
  }
  ASSERT_FALSE(covered_slots.empty());
  const GrayImage covered = covered_left_half();
  pipe.begin_frame(covered.view());
  const fe::FrameReport& r = pipe.finish(est);
  // Each covered landmark is gone at once (its slot is free, or reused by a new landmark).
  for (int s : covered_slots) {
    bool reused = false;
    for (int i = 0; i < pipe.new_landmark_count(); ++i) {
      reused = reused || pipe.new_landmark(i).slot == s;
    }
    EXPECT_TRUE(!est.used(s) || reused) << "slot " << s;
  }
  EXPECT_GE(r.deleted, static_cast<int>(covered_slots.size()));
}

TEST(FrontendPipeline, NewLandmarksStayAboveTheFloorRows) {
  fe::FramePipelineConfig cfg;
  cfg.new_landmark_max_row_fraction = 0.5;
  fe::FramePipeline pipe(cfg);
  FakeEstimator est;
  const GrayImage first = render(Warp{});
  pipe.begin_frame(first.view());
  const fe::FrameReport& r = pipe.finish(est);
  EXPECT_GT(r.initialized, 0);
  for (int i = 0; i < pipe.new_landmark_count(); ++i) {
    EXPECT_LE(pipe.new_landmark(i).v_px, 0.5 * 239.0);
  }
}
