#include <gtest/gtest.h>

#include <Eigen/Core>

#include "allocation_counter.hpp"
#include "cleanslam/slam_core/frontend/harris.hpp"
#include "cleanslam/slam_core/frontend/jcbb.hpp"
#include "cleanslam/slam_core/frontend/patch.hpp"
#include "cleanslam/slam_core/frontend/search_region.hpp"
#include "cleanslam/slam_core/frontend/tracker.hpp"
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
