#include <cstdint>
#include <limits>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "cleanslam/slam_core/ekf.hpp"

// The range the filter represents (Ekf::kMaxAbsState, Ekf::kMaxVariance): a call whose result
// would leave it is refused, counted, and changes nothing. Found by tests/fuzz/fuzz_ekf.cpp:
// finite inputs of 1e150 and beyond were taken in, and later products of them overflowed P or
// rounded J P J^T below the pixel noise.
namespace cs = cleanslam::slam_core;

namespace {

cs::EkfConfig plain_config() {
  cs::EkfConfig c;
  c.invariant_reset = false;
  return c;
}

cs::Vector6d a_pose() {
  cs::Vector6d pose;
  pose << 0.3, -0.2, 0.1, 0.0, 0.0, 0.4;
  return pose;
}

cs::OdometryIncrement a_step() {
  cs::OdometryIncrement u;
  u.dx_c = Eigen::Vector3d(0.0, 0.0, 0.1);
  u.Q.diagonal().setConstant(1e-5);
  u.dt_s = 0.5;
  return u;
}

// A filter with a landmark and two increments that correlate the pose with it, and its state and
// covariance before the call under test.
class EkfRangeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(ekf.reset(a_pose(), cs::Matrix6d::Identity() * 1e-4));
    ASSERT_GE(ekf.initialize_landmark(150.0, 110.0, 2.0, 0.3), 0);
    for (int k = 0; k < 2; ++k) {
      cs::OdometryIncrement u;
      u.dx_c = Eigen::Vector3d(0.0, 0.0, 0.1);
      u.dpsi_c = Eigen::Vector3d(0.0, -0.05, 0.0);
      u.Q.diagonal() << 1e-4, 1e-5, 1e-4, 1e-6, 1e-5, 1e-6;
      u.dt_s = 0.5;
      ASSERT_TRUE(ekf.predict(u).applied());
    }
    x0 = ekf.state();
    P0 = ekf.covariance();
  }
  void expect_unchanged() const {
    EXPECT_EQ(ekf.state(), x0);
    EXPECT_EQ(ekf.covariance(), P0);
  }
  cs::Ekf ekf{cleanslam::hal::Calibration{}, plain_config()};
  Eigen::VectorXd x0;
  Eigen::MatrixXd P0;
};

}  // namespace

TEST_F(EkfRangeTest, ResetRefusesAPoseOrCovarianceItCannotRepresent) {
  const cs::Matrix6d good = cs::Matrix6d::Identity() * 1e-4;

  cs::Vector6d far = a_pose();
  far(0) = 2.0 * cs::Ekf::kMaxAbsState;
  cs::Vector6d nan_pose = a_pose();
  nan_pose(5) = std::numeric_limits<double>::quiet_NaN();
  cs::Matrix6d huge = good;
  huge(2, 2) = 2.0 * cs::Ekf::kMaxVariance;
  cs::Matrix6d unknown_yaw = good;
  unknown_yaw(5, 5) = 2.0 * cs::Ekf::kMaxAngleVariance;
  cs::Matrix6d indefinite = good;
  indefinite(0, 1) = indefinite(1, 0) = 1e-3;  // correlation 10
  cs::Matrix6d negative = good;
  negative(4, 4) = -1e-6;
  cs::Matrix6d infinite = good;
  infinite(3, 3) = std::numeric_limits<double>::infinity();
  cs::Matrix6d overflowing = good;  // its Cholesky factor overflows to NaN, reported as success
  overflowing(3, 0) = overflowing(0, 3) = 1e307;

  EXPECT_FALSE(ekf.reset(far, good));
  EXPECT_FALSE(ekf.reset(nan_pose, good));
  EXPECT_FALSE(ekf.reset(a_pose(), huge));
  EXPECT_FALSE(ekf.reset(a_pose(), unknown_yaw));
  EXPECT_FALSE(ekf.reset(a_pose(), indefinite));
  EXPECT_FALSE(ekf.reset(a_pose(), negative));
  EXPECT_FALSE(ekf.reset(a_pose(), infinite));
  EXPECT_FALSE(ekf.reset(a_pose(), overflowing));
  expect_unchanged();
  EXPECT_EQ(ekf.landmark_count(), 1);

  // A zero covariance (a pose taken as known) and a rank-deficient one are semi-definite.
  cs::Matrix6d rank_one = cs::Matrix6d::Zero();
  rank_one(0, 0) = rank_one(1, 1) = rank_one(0, 1) = rank_one(1, 0) = 1e-4;
  EXPECT_TRUE(ekf.reset(a_pose(), rank_one));
  EXPECT_TRUE(ekf.reset(a_pose(), cs::Matrix6d::Zero()));
  EXPECT_EQ(ekf.landmark_count(), 0);
}

TEST_F(EkfRangeTest, PredictionBeyondTheRangeIsRefused) {
  const std::uint64_t rejected = ekf.counters().predictions_rejected;

  cs::OdometryIncrement far = a_step();
  far.dx_c(2) = 2.0 * cs::Ekf::kMaxAbsState;
  cs::OdometryIncrement uncertain = a_step();
  uncertain.Q(0, 0) = 2.0 * cs::Ekf::kMaxVariance;
  cs::OdometryIncrement turn_unknown = a_step();
  turn_unknown.Q(5, 5) = 2.0 * cs::Ekf::kMaxAngleVariance;
  EXPECT_EQ(ekf.predict(far).result, cs::PredictResult::kOutOfRange);
  EXPECT_EQ(ekf.predict(uncertain).result, cs::PredictResult::kOutOfRange);
  EXPECT_EQ(ekf.predict(turn_unknown).result, cs::PredictResult::kOutOfRange);
  expect_unchanged();
  EXPECT_EQ(ekf.counters().predictions_rejected, rejected + 3);

  // Inside the range (a kilometre, a variance of 1e6 m^2, a heading variance of 10 rad^2) it is
  // applied.
  cs::OdometryIncrement long_step = a_step();
  long_step.dx_c(2) = 1e3;
  long_step.Q(0, 0) = 1e6;
  long_step.Q(5, 5) = 10.0;
  EXPECT_TRUE(ekf.predict(long_step).applied());
}

TEST_F(EkfRangeTest, LandmarkBeyondTheRangeIsNotInitialized) {
  const cs::RejectionCounters before = ekf.counters().rejections;

  EXPECT_EQ(ekf.initialize_landmark(160.0, 120.0, 2.0 * cs::Ekf::kMaxAbsState, 0.3), -1);
  EXPECT_EQ(ekf.initialize_landmark(160.0, 120.0, 2.0, 1e7), -1);  // eps_ct^2 of 1e14 m^2
  expect_unchanged();
  EXPECT_EQ(ekf.counters().rejections[cs::ObservationResult::kOutOfRange],
            before[cs::ObservationResult::kOutOfRange] + 2);
  EXPECT_EQ(ekf.counters().rejections[cs::ObservationResult::kNonFinite],
            before[cs::ObservationResult::kNonFinite]);

  // The paper's largest eps_ct (1000 m) is inside it.
  EXPECT_GE(ekf.initialize_landmark(160.0, 120.0, 5.0, 1000.0), 0);
}

// The run's summary lists the filter's refusals by these names.
TEST(EkfRange, EveryRefusalHasANameOfItsOwn) {
  std::set<std::string> names;
  for (int i = 0; i < cs::kObservationResultCount; ++i) {
    const std::string name = cs::to_string(static_cast<cs::ObservationResult>(i));
    EXPECT_NE(name, "unknown") << i;
    EXPECT_TRUE(names.insert(name).second) << name;
  }
  EXPECT_EQ(std::string(cs::to_string(cs::ObservationResult::kOutOfRange)), "out_of_range");
}
