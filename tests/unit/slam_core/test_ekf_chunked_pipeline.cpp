#include <gtest/gtest.h>

#include "cleanslam/slam_core/frontend/frame_pipeline.hpp"
#include "frontend_fake_estimator.hpp"
#include "frontend_synthetic.hpp"

namespace fe = cleanslam::slam_core::frontend;
using cleanslam::test::FakeEstimator;
using cleanslam::test::GrayImage;
using cleanslam::test::render;
using cleanslam::test::Warp;

namespace {

// An estimator whose update takes `parts` further continue_update() calls; nothing else may be
// asked of it meanwhile.
class PendingEstimator final : public FakeEstimator {
 public:
  int parts = 3;
  int continued = 0;
  int calls_while_pending = 0;

  int update(const fe::PixelObservation* obs, int count) override {
    check();
    FakeEstimator::update(obs, count);
    pending_ = parts;
    fused_ = count;
    return 0;
  }
  [[nodiscard]] bool update_pending() const override { return pending_ > 0; }
  bool continue_update(int& fused) override {
    ++continued;
    fused = 0;
    if (pending_ == 0 || --pending_ > 0) {
      return pending_ == 0;
    }
    fused = fused_;
    return true;
  }
  bool predict_pixel(int slot, cleanslam::slam_core::frontend::PixelPrediction& out) override {
    check();
    return FakeEstimator::predict_pixel(slot, out);
  }
  int initialize_landmark(double u_px, double v_px) override {
    check();
    return FakeEstimator::initialize_landmark(u_px, v_px);
  }
  void delete_landmark(int slot) override {
    check();
    FakeEstimator::delete_landmark(slot);
  }

 private:
  void check() { calls_while_pending += pending_ > 0 ? 1 : 0; }
  int pending_ = 0;
  int fused_ = 0;
};

}  // namespace

TEST(FrontendPipelinePendingUpdate, FuseStageStepsUntilTheUpdateIsComplete) {
  fe::FramePipeline pipe;
  PendingEstimator est;
  const GrayImage first = render(Warp{});
  pipe.begin_frame(first.view());
  pipe.finish(est);
  ASSERT_GT(pipe.report().initialized, 5);
  Warp w;
  w.shift_x = 2.0;
  est.belief = w;
  const GrayImage img = render(w);
  pipe.begin_frame(img.view());
  int fuse_steps = 0;
  bool manage_after_fuse = false;
  fe::FrameStage previous = pipe.stage();
  while (true) {
    const fe::FrameStage before = pipe.stage();
    if (before == fe::FrameStage::kFuse) {
      ++fuse_steps;
      EXPECT_FALSE(pipe.report().updated);
    }
    manage_after_fuse = manage_after_fuse ||
                        (previous == fe::FrameStage::kFuse && before == fe::FrameStage::kManage);
    previous = before;
    if (!pipe.step(est)) {
      break;
    }
  }
  EXPECT_EQ(est.updates, 1);
  EXPECT_EQ(fuse_steps, est.parts);
  EXPECT_EQ(est.continued, est.parts);
  EXPECT_TRUE(manage_after_fuse);
  EXPECT_EQ(est.calls_while_pending, 0);
  EXPECT_GT(pipe.report().fused, 5);
  EXPECT_EQ(pipe.report().fused, est.last_fused);
  EXPECT_TRUE(pipe.report().updated);
}

TEST(FrontendPipelinePendingUpdate, AnUpdateCompleteAtOnceSkipsTheFuseStage) {
  fe::FramePipeline pipe;
  PendingEstimator est;
  est.parts = 0;
  const GrayImage first = render(Warp{});
  pipe.begin_frame(first.view());
  pipe.finish(est);
  Warp w;
  w.shift_x = 2.0;
  est.belief = w;
  const GrayImage img = render(w);
  pipe.begin_frame(img.view());
  while (true) {
    EXPECT_NE(pipe.stage(), fe::FrameStage::kFuse);
    if (!pipe.step(est)) {
      break;
    }
  }
  EXPECT_EQ(est.updates, 1);
  EXPECT_EQ(est.continued, 0);
  EXPECT_EQ(pipe.report().fused, 0);  // this estimator reports its fused count only when pending
}
