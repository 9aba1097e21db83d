#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <span>

#include <Eigen/Core>

#include "cleanslam/slam_core/frontend/ekf_adapter.hpp"

namespace fe = cleanslam::slam_core::frontend;

namespace {

// The EKF's API shape (ekf branch), recording what the adapter passes through.
struct MockObservation {
  int slot = -1;
  double u_px = 0.0;
  double v_px = 0.0;
};
struct MockPrediction {
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
  double depth_m = 0.0;
  bool in_front = false;
};
struct MockStatus {
  int fused = 0;
};

struct MockEkf {
  MockStatus status;
  int last_count = -1;
  MockObservation last[cleanslam::hal::kMaxObservationsPerFrame];
  int deleted = -1;
  bool predict_pixel(int slot, MockPrediction& out) const {
    if (slot != 3) {
      return false;
    }
    out.uv = {100.0, 50.0};
    out.S << 4.0, 1.0, 1.0, 9.0;
    out.depth_m = 2.5;
    out.in_front = true;
    return true;
  }
  int joint_pixel_innovation(std::span<const MockObservation> obs, std::span<double> nu,
                             std::span<double> S) const {
    for (std::size_t i = 0; i < obs.size(); ++i) {
      nu[2 * i] = obs[i].u_px - 100.0;
      nu[2 * i + 1] = obs[i].v_px - 50.0;
    }
    std::fill(S.begin(), S.begin() + static_cast<std::ptrdiff_t>(4 * obs.size() * obs.size()), 0.0);
    return static_cast<int>(obs.size());
  }
  int initialize_landmark(double u_px, double v_px) { return u_px > 0.0 && v_px > 0.0 ? 7 : -1; }
  void delete_landmark(int slot) { deleted = slot; }
  const MockStatus& update(const MockObservation* obs, int count) {
    last_count = count;
    for (int i = 0; i < count; ++i) {
      last[i] = obs[i];
    }
    status.fused = count - 1;
    return status;
  }
};

using Adapter = fe::EkfAdapter<MockEkf, MockObservation, MockPrediction>;

}  // namespace

TEST(FrontendEkfAdapter, PassesCallsThroughUnchanged) {
  MockEkf ekf;
  Adapter adapter(ekf);
  fe::PixelPrediction p;
  EXPECT_FALSE(adapter.predict_pixel(2, p));
  ASSERT_TRUE(adapter.predict_pixel(3, p));
  EXPECT_EQ(p.uv, Eigen::Vector2d(100.0, 50.0));
  EXPECT_EQ(p.S(0, 1), 1.0);
  EXPECT_EQ(p.S(1, 1), 9.0);
  EXPECT_EQ(p.depth_m, 2.5);
  EXPECT_TRUE(p.in_front);

  const fe::PixelObservation obs[2] = {{3, 101.0, 52.0}, {5, 90.0, 40.0}};
  double nu[4];
  double S[16];
  EXPECT_EQ(adapter.joint_pixel_innovation(obs, nu, S), 2);
  EXPECT_EQ(nu[0], 1.0);
  EXPECT_EQ(nu[3], -10.0);
  EXPECT_EQ(adapter.update(obs, 2), 1);
  ASSERT_EQ(ekf.last_count, 2);
  EXPECT_EQ(ekf.last[1].slot, 5);
  EXPECT_EQ(ekf.last[1].u_px, 90.0);
  EXPECT_EQ(adapter.initialize_landmark(10.0, 20.0), 7);
  EXPECT_EQ(adapter.initialize_landmark(-1.0, 20.0), -1);
  adapter.delete_landmark(9);
  EXPECT_EQ(ekf.deleted, 9);
}

TEST(FrontendEkfAdapter, RejectsMoreObservationsThanAFrameHolds) {
  MockEkf ekf;
  Adapter adapter(ekf);
  fe::PixelObservation obs[cleanslam::hal::kMaxObservationsPerFrame + 1] = {};
  double nu[2];
  double S[4];
  EXPECT_EQ(adapter.joint_pixel_innovation(obs, nu, S), -1);
  EXPECT_EQ(adapter.update(obs, -1), 0);
  EXPECT_EQ(ekf.last_count, -1);
}

namespace {

// An estimator that also has the position API (camera_pose, landmark, slot_used).
struct MockEkfWithPositions : MockEkf {
  Eigen::Matrix<double, 6, 1> camera_pose() const {
    Eigen::Matrix<double, 6, 1> p;
    p << 1.0, 2.0, 0.1, 0.0, 0.0, 0.5;
    return p;
  }
  bool slot_used(int slot) const { return slot == 3; }
  Eigen::Vector3d landmark(int slot) const {
    return Eigen::Vector3d(4.0, 2.0, static_cast<double>(slot));
  }
};

}  // namespace

TEST(FrontendEkfAdapter, PositionsOnlyWhenTheEstimatorHasThem) {
  MockEkf plain;
  fe::EkfAdapter<MockEkf, MockObservation, MockPrediction> a(plain);
  Eigen::Vector3d out(9.0, 9.0, 9.0);
  EXPECT_FALSE(a.camera_position(out));
  EXPECT_FALSE(a.landmark_position(3, out));

  MockEkfWithPositions full;
  fe::EkfAdapter<MockEkfWithPositions, MockObservation, MockPrediction> b(full);
  ASSERT_TRUE(b.camera_position(out));
  EXPECT_EQ(out, Eigen::Vector3d(1.0, 2.0, 0.1));
  ASSERT_TRUE(b.landmark_position(3, out));
  EXPECT_EQ(out, Eigen::Vector3d(4.0, 2.0, 3.0));
  EXPECT_FALSE(b.landmark_position(5, out));  // unused slot
}
