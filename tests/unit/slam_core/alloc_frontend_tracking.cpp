#include <gtest/gtest.h>

#include <Eigen/Core>

#include <vector>

#include "allocation_counter.hpp"
#include "cleanslam/slam_core/frontend/frame_pipeline.hpp"
#include "cleanslam/slam_core/frontend/harris.hpp"
#include "cleanslam/slam_core/frontend/jcbb.hpp"
#include "cleanslam/slam_core/frontend/patch.hpp"
#include "cleanslam/slam_core/frontend/search_region.hpp"
#include "cleanslam/slam_core/frontend/tracker.hpp"
#include "frontend_fake_estimator.hpp"
#include "frontend_synthetic.hpp"

namespace fe = cleanslam::slam_core::frontend;
using cleanslam::test::GrayImage;
using cleanslam::test::render;
using cleanslam::test::Warp;

// After construction, a frame's detection, patch capture, template resampling, tracking, search
// regions and JCBB allocate nothing (operator new and Eigen's malloc both checked).
TEST(FrontendAllocation, FrameProcessingAllocatesNothing) {
  const GrayImage ref = render(Warp{});
  Warp w;
  w.shift_x = 3.5;
  w.scale = 1.1;
  const GrayImage cur = render(w);
  const GrayImage wrong(160, 120, 0);
  fe::HarrisDetector det;
  fe::PatchStore store;
  const fe::Tracker tracker;
  fe::Jcbb jcbb;
  constexpr int kM = fe::Jcbb::kMaxObservations;
  double nu[2 * kM];
  double S[4 * kM * kM] = {};
  bool inlier[kM];
  int tracked = 0;
  int slots = 0;
  double u0[kM];
  double v0[kM];
  fe::JcbbResult jr;
  std::size_t allocations = 0;
  {
    Eigen::internal::set_is_malloc_allowed(false);
    const cleanslam::test::AllocationScope scope;
    det.detect(ref.view(), 320, 240);
    det.detect(wrong.view(), 320, 240);
    det.detect(ref.view(), 320, 240);
    for (int i = 0; i < det.corner_count() && slots < kM; ++i) {
      const fe::Corner& c = det.corners()[i];
      if (c.x > 40 && c.x < 280 && c.y > 40 && c.y < 200 &&
          store.capture(slots, ref.view(), c.x, c.y, 2.0)) {
        u0[slots] = c.x;
        v0[slots] = c.y;
        ++slots;
      }
    }
    det.detect(cur.view(), 320, 240);
    int m = 0;
    for (int s = 0; s < slots; ++s) {
      const fe::LandmarkPatch* p = store.get(s);
      double tu = 0.0;
      double tv = 0.0;
      w.apply(u0[s], v0[s], tu, tv);
      fe::PixelPrediction pred;
      pred.S = Eigen::Matrix2d::Identity() * 4.0;
      pred.depth_m = 2.0 / 1.1;
      pred.in_front = true;
      pred.uv = Eigen::Vector2d(tu + 1.0, tv - 1.0);
      const fe::SearchRegion region = fe::make_search_region(pred, 320, 240);
      fe::PatchTemplate tmpl;
      if (p != nullptr &&
          fe::make_template(*p, fe::predicted_patch_scale(p->first_depth_m, pred.depth_m), 3.0F,
                            tmpl)) {
        const fe::TrackResult r =
            tracker.track(cur.view(), tmpl, region, det.corners(), det.corner_count());
        if (r.found) {
          ++tracked;
          nu[2 * m] = r.u_px - tu;
          nu[2 * m + 1] = r.v_px - tv;
          ++m;
        }
      }
    }
    for (int i = 0; i < 2 * m; ++i) {
      S[i * 2 * m + i] = 4.0;
    }
    jr = jcbb.solve(nu, S, m, inlier);
    allocations = scope.count();
    Eigen::internal::set_is_malloc_allowed(true);
  }
  EXPECT_EQ(allocations, 0U);
  EXPECT_GT(det.corner_count(), 0);
  EXPECT_EQ(slots, kM);
  EXPECT_GE(tracked, kM - 2);
  EXPECT_EQ(jr.inlier_count, tracked);
}

// Whole frames through the resumable pipeline (initialization, tracking, JCBB, update, deletion,
// a rejected frame and a featureless one) allocate nothing after construction.
TEST(FrontendAllocation, FramePipelineAllocatesNothing) {
  fe::FramePipeline pipe;
  cleanslam::test::FakeEstimator est;
  std::vector<GrayImage> frames;
  for (int k = 0; k < 4; ++k) {
    Warp w;
    w.scale = 1.0 + 0.05 * k;
    w.shift_x = 2.0 * k;
    frames.push_back(render(w));
  }
  GrayImage covered = frames[3];
  for (int y = 0; y < 240; ++y) {
    for (int x = 0; x < 160; ++x) {
      covered.at(x, y) = 90;
    }
  }
  const GrayImage black(320, 240, 0);
  const GrayImage wrong(100, 100, 0);
  int tracked = 0;
  int updates = 0;
  int active_before = 0;
  int forgotten_active = -1;
  std::size_t allocations = 0;
  {
    Eigen::internal::set_is_malloc_allowed(false);
    const cleanslam::test::AllocationScope scope;
    for (int k = 0; k < 4; ++k) {
      est.belief.scale = 1.0 + 0.05 * k;
      est.belief.shift_x = 2.0 * k;
      pipe.begin_frame(frames[static_cast<std::size_t>(k)].view());
      tracked += pipe.finish(est).tracked;
    }
    for (int k = 0; k < 3; ++k) {
      pipe.begin_frame(covered.view());
      pipe.finish(est);
    }
    pipe.begin_frame(black.view());
    pipe.finish(est);
    pipe.begin_frame(wrong.view());
    pipe.finish(est);
    // A new map after a lift: the front end forgets its landmarks without allocating.
    active_before = pipe.book().active_count();
    pipe.forget_map();
    forgotten_active = pipe.book().active_count();
    updates = est.updates;
    allocations = scope.count();
    Eigen::internal::set_is_malloc_allowed(true);
  }
  EXPECT_EQ(allocations, 0U);
  EXPECT_GE(tracked, 25);
  EXPECT_GE(updates, 3);
  EXPECT_GT(est.deletions, 0);
  EXPECT_GT(active_before, 0);
  EXPECT_EQ(forgotten_active, 0);
}
