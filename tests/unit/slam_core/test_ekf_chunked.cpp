#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "cleanslam/slam_core/ekf.hpp"

namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

constexpr int kLandmarks = 100;

// Two filters fed the same calls: one updates at once, the other in bounded steps.
class EkfChunkedTest : public ::testing::Test {
 protected:
  void SetUp() override {
    calibration_.camera.distortion = {-0.1, 0.02, 0.0005, -0.0003};
    cs::EkfConfig config;
    config.invariant_reset = invariant_reset_;
    one_ = std::make_unique<cs::Ekf>(calibration_, config);
    chunked_ = std::make_unique<cs::Ekf>(calibration_, config);
    for (cs::Ekf* e : {one_.get(), chunked_.get()}) {
      cs::Vector6d pose;
      pose << 0.3, -0.2, 0.1, 0.01, -0.02, 0.4;
      cs::Vector6d d;
      d << 1e-4, 1e-4, 1e-6, 1e-6, 1e-6, 1e-4;
      EXPECT_TRUE(e->reset(pose, d.asDiagonal()));
    }
  }
  void both(void (*fn)(cs::Ekf&)) {
    fn(*one_);
    fn(*chunked_);
  }
  static void move(cs::Ekf& e) {
    cs::OdometryIncrement u;
    u.dx_c = Eigen::Vector3d(0.05, 0.0, 0.0);
    u.dpsi_c = Eigen::Vector3d(0.0, 0.0, 0.02);
    u.Q.diagonal() << 1e-4, 1e-5, 1e-6, 1e-6, 1e-6, 1e-5;
    ASSERT_TRUE(e.predict(u).applied());
  }
  static void add_landmarks(cs::Ekf& e) {
    for (int i = 0; i < kLandmarks; ++i) {
      const double u = 30.0 + static_cast<double>((i * 37) % 260);
      const double v = 20.0 + static_cast<double>((i * 53) % 200);
      // Half young (the consider update), half at a known depth (the full update).
      if (i % 2 == 0) {
        e.initialize_landmark(u, v);
      } else {
        e.initialize_landmark(u, v, 2.0 + 0.02 * static_cast<double>(i), 0.05);
      }
    }
  }
  // Observations of up to 16 used slots from `first`, near their predicted pixels (one filter's
  // predictions: the two filters agree before the update).
  int observe(int first, std::array<cs::Observation, hal::kMaxObservationsPerFrame>& obs) const {
    int m = 0;
    for (int s = first; s < hal::kMaxLandmarks && m < hal::kMaxObservationsPerFrame; ++s) {
      cs::PixelPrediction p;
      if (one_->predict_pixel(s, p)) {
        const double du = 0.4 * static_cast<double>((s * 7) % 5 - 2);
        const double dv = 0.3 * static_cast<double>((s * 11) % 5 - 2);
        obs[static_cast<std::size_t>(m++)] = {s, p.uv.x() + du, p.uv.y() + dv};
      }
    }
    return m;
  }
  // Relative difference of the two filters' states and covariances.
  double difference() const {
    const int n = one_->active_dim();
    EXPECT_EQ(n, chunked_->active_dim());
    const cs::Ekf::StateMatrix& P1 = one_->covariance();
    const cs::Ekf::StateMatrix& P2 = chunked_->covariance();
    const cs::Ekf::StateVector& x1 = one_->state();
    const cs::Ekf::StateVector& x2 = chunked_->state();
    double dP = 0.0;
    double sP = 0.0;
    double dx = 0.0;
    double sx = 0.0;
    for (int c = 0; c < n; ++c) {
      for (int r = 0; r < n; ++r) {
        dP = std::max(dP, std::abs(P1(r, c) - P2(r, c)));
        sP = std::max(sP, std::abs(P1(r, c)));
      }
      dx = std::max(dx, std::abs(x1(c) - x2(c)));
      sx = std::max(sx, std::abs(x1(c)));
    }
    return std::max(dP / sP, dx / sx);
  }
  // Runs the chunked filter's pending update to its end; returns the calls it took (update's
  // own included).
  int complete() {
    int calls = 1;
    while (chunked_->update_pending()) {
      const bool done = chunked_->continue_update();
      EXPECT_EQ(done, !chunked_->update_pending());
      ++calls;
    }
    return calls;
  }

  hal::Calibration calibration_;
  bool invariant_reset_ = false;  // EkfConfig::invariant_reset: SetUp() again after a change
  std::unique_ptr<cs::Ekf> one_;
  std::unique_ptr<cs::Ekf> chunked_;
};

}  // namespace

TEST_F(EkfChunkedTest, WithoutBudgetTheUpdateCompletesAtOnce) {
  EXPECT_EQ(chunked_->update_step(), 0);
  both(&move);
  both(&add_landmarks);
  both(&move);
  std::array<cs::Observation, hal::kMaxObservationsPerFrame> obs{};
  const int m = observe(0, obs);
  ASSERT_GT(m, 8);
  EXPECT_GT(chunked_->update(obs.data(), m).fused, 0);
  EXPECT_FALSE(chunked_->update_pending());
  EXPECT_TRUE(chunked_->continue_update());
}

TEST_F(EkfChunkedTest, ChunkedUpdatesEqualOneShotUpdates) {
  for (const bool invariant_reset : {false, true}) {
    invariant_reset_ = invariant_reset;
    for (const std::int64_t budget : {std::int64_t{1}, std::int64_t{20000}, std::int64_t{300000}}) {
      SetUp();
      chunked_->set_update_step(budget);
      both(&move);
      both(&add_landmarks);
      ASSERT_GT(one_->landmark_count(), 90);
      int previous_calls = 1 << 30;
      for (int round = 0; round < 6; ++round) {
        both(&move);
        std::array<cs::Observation, hal::kMaxObservationsPerFrame> obs{};
        const int m = observe((round * 16) % kLandmarks, obs);
        ASSERT_GT(m, 4);
        const cs::UpdateStatus& a = one_->update(obs.data(), m);
        chunked_->update(obs.data(), m);
        EXPECT_TRUE(chunked_->update_pending());
        const int calls = complete();
        const cs::UpdateStatus& b = chunked_->last_update();
        ASSERT_GT(a.fused, 0);
        EXPECT_EQ(a.fused, b.fused);
        EXPECT_EQ(a.rejected, b.rejected);
        EXPECT_EQ(a.applied, b.applied);
        for (int i = 0; i < a.count; ++i) {
          EXPECT_EQ(a.observations[static_cast<std::size_t>(i)].result,
                    b.observations[static_cast<std::size_t>(i)].result);
        }
        EXPECT_LE(difference(), 1e-12)
            << "budget " << budget << " round " << round << " invariant " << invariant_reset;
        // The whole update is many calls under a small budget, a few under a large one.
        EXPECT_GT(calls, budget == 1 ? chunked_->active_dim() : 2);
        if (round == 0) {
          previous_calls = calls;
        }
      }
      EXPECT_GT(previous_calls, 1);
      EXPECT_EQ(one_->counters().updates_applied, chunked_->counters().updates_applied);
      EXPECT_EQ(one_->counters().consider_observations, chunked_->counters().consider_observations);
    }
  }
}

TEST_F(EkfChunkedTest, PoseIsPriorOrPosteriorWhilePending) {
  for (const bool invariant_reset : {false, true}) {
    invariant_reset_ = invariant_reset;
    SetUp();
    chunked_->set_update_step(20000);
    both(&move);
    both(&add_landmarks);
    both(&move);
    std::array<cs::Observation, hal::kMaxObservationsPerFrame> obs{};
    const int m = observe(0, obs);
    const cs::Vector6d prior = chunked_->camera_pose();
    const cs::Matrix6d prior_cov = chunked_->pose_covariance();
    one_->update(obs.data(), m);
    const cs::Vector6d posterior = one_->camera_pose();
    const cs::Matrix6d posterior_cov = one_->pose_covariance();
    ASSERT_GT((posterior - prior).norm(), 0.0);
    const int in_view = one_->body_pose_estimate(0).landmarks_in_view;
    ASSERT_GT(in_view, 0);
    chunked_->update(obs.data(), m);
    int prior_steps = 0;
    int posterior_steps = 0;
    while (chunked_->update_pending()) {
      const int view = chunked_->body_pose_estimate(0).landmarks_in_view;
      if (chunked_->camera_pose() == prior) {
        EXPECT_EQ(chunked_->pose_covariance(), prior_cov);
        EXPECT_GE(view, in_view);  // the candidates; the depth bounds may drop some
        ++prior_steps;
      } else {
        EXPECT_EQ(chunked_->camera_pose(), posterior);
        EXPECT_EQ(chunked_->pose_covariance(), posterior_cov);
        EXPECT_EQ(view, in_view);
        ++posterior_steps;
      }
      chunked_->continue_update();
    }
    EXPECT_GT(prior_steps, 0);      // the gain rows
    EXPECT_GT(posterior_steps, 0);  // the covariance columns
    EXPECT_LE(difference(), 1e-12);
  }
}

TEST_F(EkfChunkedTest, CallsThatChangeTheFilterFinishAPendingUpdateFirst) {
  chunked_->set_update_step(1);
  both(&move);
  both(&add_landmarks);
  both(&move);
  std::array<cs::Observation, hal::kMaxObservationsPerFrame> obs{};
  const int m = observe(0, obs);
  one_->update(obs.data(), m);
  chunked_->update(obs.data(), m);
  chunked_->continue_update();
  ASSERT_TRUE(chunked_->update_pending());
  both(&move);  // the chunked filter's predict completes its update, then predicts
  EXPECT_FALSE(chunked_->update_pending());
  EXPECT_LE(difference(), 1e-12);

  const int m2 = observe(20, obs);
  one_->update(obs.data(), m2);
  chunked_->update(obs.data(), m2);
  ASSERT_TRUE(chunked_->update_pending());
  EXPECT_EQ(one_->initialize_landmark(150.0, 100.0), chunked_->initialize_landmark(150.0, 100.0));
  EXPECT_FALSE(chunked_->update_pending());
  EXPECT_LE(difference(), 1e-12);

  chunked_->update(obs.data(), m2);
  ASSERT_TRUE(chunked_->update_pending());
  EXPECT_TRUE(chunked_->reset(cs::Vector6d::Zero(), cs::Matrix6d::Identity()));
  EXPECT_FALSE(chunked_->update_pending());
  EXPECT_EQ(chunked_->landmark_count(), 0);
}
