#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "cleanslam/slam_core/dead_reckoner.hpp"
#include "cleanslam/slam_core/geometry.hpp"
#include "numeric_jacobian.hpp"
#include "symmetric_eigen.hpp"
#include "time_units.hpp"

namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

using cleanslam::test::kMs;

// Drives a differential robot with body speed v(t) and yaw rate w(t): exact wheel ticks at 20 Hz
// (from an arbitrary start count) and a gyro at 100 Hz with a constant bias, fed in time order.
class Drive {
 public:
  Drive(cs::DeadReckoner& dr, const hal::Calibration& cal) : dr_(dr), cal_(cal) {}
  std::function<double(double)> v = [](double) { return 0.0; };
  std::function<double(double)> w = [](double) { return 0.0; };
  double gyro_bias = 0.0;
  double gyro_noise = 0.0;
  bool gyro_on = true;
  std::int32_t start_ticks = 0;
  double left_scale = 1.0;  // the wheels count this many times their true travel
  double right_scale = 1.0;

  // Advances to t_end (ms resolution integration of the true motion).
  void run_until(hal::TimeNs t_end) {
    for (; t_ <= t_end; t_ += kMs) {
      const double ts = hal::to_seconds(t_);
      if (t_ > 0) {
        const double dt = 1e-3;
        const double vv = v(ts);
        const double ww = w(ts);
        left_ += (vv - 0.5 * cal_.wheels.wheel_base * ww) * dt;
        right_ += (vv + 0.5 * cal_.wheels.wheel_base * ww) * dt;
        const double mid = yaw + 0.5 * ww * dt;
        x += vv * dt * std::cos(mid);
        y += vv * dt * std::sin(mid);
        yaw += ww * dt;
      }
      if (gyro_on && t_ % (10 * kMs) == 0) {
        hal::GyroSample g;
        g.t_ns = t_;
        g.wz_rad_s = w(ts) + gyro_bias + gyro_noise * noise_(rng_);
        dr_.add_gyro(g);
      }
      if (t_ % (50 * kMs) == 0) {
        hal::EncoderSample e;
        e.t_ns = t_;
        e.left_ticks = ticks(left_scale * left_ * cal_.wheels.ticks_per_meter_left);
        e.right_ticks = ticks(right_scale * right_ * cal_.wheels.ticks_per_meter_right);
        dr_.add_encoder(e);
      }
    }
  }
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;

 private:
  std::int32_t ticks(double count) const {
    const auto c = static_cast<std::int64_t>(std::llround(count));
    return static_cast<std::int32_t>(
        static_cast<std::uint32_t>(static_cast<std::int64_t>(start_ticks) + c));
  }
  cs::DeadReckoner& dr_;
  hal::Calibration cal_;
  hal::TimeNs t_ = 0;
  double left_ = 0.0;
  double right_ = 0.0;
  std::mt19937 rng_{7};
  std::normal_distribution<double> noise_{0.0, 1.0};
};

// The gyro's heading alone, without the persistent-error terms and the wheel-yaw fusion the robot
// runs with (DeadReckoningConfig's defaults): the tests that isolate the gyro's mechanism, or
// compare another against it, set these explicitly.
cs::DeadReckoningConfig gyro_only() {
  cs::DeadReckoningConfig c;
  c.gyro_bias_correlation_time_s = 0.0;
  c.gyro_scale_error = 0.0;
  c.wheel_yaw.enabled = false;
  return c;
}

}  // namespace

TEST(DeadReckoner, StraightLineIncrementsSumToTravelledDistance) {
  const hal::Calibration cal;
  cs::DeadReckoner dr(cal, cs::DeadReckoningConfig{});
  Drive drive(dr, cal);
  drive.v = [](double) { return 0.2; };
  drive.run_until(0);
  dr.take_increment(0);
  double total = 0.0;
  // Frames at irregular times between encoder samples.
  for (hal::TimeNs t : {1013 * kMs, 1988 * kMs, 3041 * kMs, 4000 * kMs, 5027 * kMs}) {
    drive.run_until(t);
    const cs::OdometryIncrement u = dr.take_increment(t);
    EXPECT_TRUE(u.gyro_used);
    EXPECT_NEAR(u.dpsi_c.z(), 0.0, 1e-9);
    EXPECT_NEAR(u.dx_c.y(), 0.0, 1e-9);
    total += u.dx_c.x();
  }
  drive.run_until(6000 * kMs);
  total += dr.take_increment(6000 * kMs).dx_c.x();
  EXPECT_NEAR(total, 0.2 * 6.0, 1e-3);
  EXPECT_NEAR(dr.x(), 1.2, 1e-3);
}

TEST(DeadReckoner, InterpolatesToFrameTime) {
  const hal::Calibration cal;
  cs::DeadReckoner dr(cal, cs::DeadReckoningConfig{});
  Drive drive(dr, cal);
  drive.v = [](double) { return 0.3; };
  drive.run_until(1000 * kMs);
  dr.take_increment(1000 * kMs);
  drive.run_until(1530 * kMs);  // last encoder sample at 1.5 s
  const cs::OdometryIncrement u = dr.take_increment(1530 * kMs);
  EXPECT_NEAR(u.dx_c.x(), 0.3 * 0.53, 1e-3);
  EXPECT_NEAR(u.dt_s, 0.53, 1e-12);
  drive.run_until(2000 * kMs);
  EXPECT_NEAR(dr.take_increment(2000 * kMs).dx_c.x(), 0.3 * 0.47, 1e-3);
}

TEST(DeadReckoner, ArcMatchesTrueMotionThroughTheExtrinsic) {
  const hal::Calibration cal;  // camera 0.10 m ahead of the wheel axis, 0.08 m up
  cs::DeadReckoner dr(cal, gyro_only());
  Drive drive(dr, cal);
  drive.v = [](double) { return 0.2; };
  drive.w = [](double) { return 0.4; };
  drive.run_until(0);
  dr.take_increment(0);
  drive.run_until(2000 * kMs);
  const cs::OdometryIncrement u = dr.take_increment(2000 * kMs);
  // Camera displacement in the first camera frame: body displacement plus the lever arm.
  const double yaw = 0.8;
  const Eigen::Vector3d body(drive.x, drive.y, 0.0);
  const Eigen::Vector3d lever(0.10, 0.0, 0.08);
  const Eigen::Vector3d expected = body + cs::rotation_zyx(0, 0, yaw) * lever - lever;
  EXPECT_LT((u.dx_c - expected).norm(), 2e-3);
  EXPECT_NEAR(u.dpsi_c.z(), yaw, 1e-3);
  EXPECT_NEAR(dr.yaw(), yaw, 1e-3);
  EXPECT_NEAR(dr.x(), drive.x, 2e-3);
  EXPECT_NEAR(dr.y(), drive.y, 2e-3);
  EXPECT_NEAR(u.distance_m, 0.4, 1e-3);
  // Q: symmetric positive semi-definite, with yaw variance from the gyro model.
  EXPECT_LT((u.Q - u.Q.transpose()).norm(), 1e-15);
  EXPECT_GT(cleanslam::test::min_eigenvalue(u.Q), -1e-15);
  const double nd = cal.gyro.noise_density;
  const double bi = cal.gyro.bias_instability;
  EXPECT_NEAR(u.Q(5, 5), nd * nd * 2.0 + bi * bi * 4.0, 1e-9);
  EXPECT_GT(u.Q(2, 2), 0.0);  // z uncertainty grows with distance
  EXPECT_GT(u.Q(3, 3), 0.0);
}

TEST(DeadReckoner, StraightLineDistanceVarianceIsScaleError) {
  const hal::Calibration cal;
  cs::DeadReckoningConfig config;
  config.z_noise_m_per_sqrt_m = 0.0;
  config.roll_pitch_noise_rad_per_sqrt_m = 0.0;
  cs::DeadReckoner dr(cal, config);
  Drive drive(dr, cal);
  drive.v = [](double) { return 0.25; };
  drive.run_until(0);
  dr.take_increment(0);
  drive.run_until(2000 * kMs);
  const cs::OdometryIncrement u = dr.take_increment(2000 * kMs);
  const double k = cal.wheels.distance_noise;
  EXPECT_NEAR(u.Q(0, 0), k * k * 0.5 * 0.5, 1e-9);
  // Heading errors show up laterally: y variance grows with distance.
  EXPECT_GT(u.Q(1, 1), 0.0);
}

TEST(DeadReckoner, UsesEncodersWithInflatedNoiseWhenGyroIsSilent) {
  const hal::Calibration cal;
  cs::DeadReckoner with_gyro(cal, cs::DeadReckoningConfig{});
  cs::DeadReckoner without(cal, cs::DeadReckoningConfig{});
  Drive a(with_gyro, cal);
  Drive b(without, cal);
  for (Drive* d : {&a, &b}) {
    d->v = [](double) { return 0.2; };
    d->w = [](double) { return 0.3; };
  }
  b.gyro_on = false;
  a.run_until(0);
  b.run_until(0);
  with_gyro.take_increment(0);
  without.take_increment(0);
  a.run_until(1000 * kMs);
  b.run_until(1000 * kMs);
  const cs::OdometryIncrement ua = with_gyro.take_increment(1000 * kMs);
  const cs::OdometryIncrement ub = without.take_increment(1000 * kMs);
  EXPECT_TRUE(ua.gyro_used);
  EXPECT_FALSE(ub.gyro_used);
  EXPECT_NEAR(ub.dpsi_c.z(), 0.3, 2e-3);
  EXPECT_GT(ub.Q(5, 5), 100.0 * ua.Q(5, 5));
  EXPECT_GT(without.counters().steps_without_gyro, 0U);
  EXPECT_TRUE(without.gyro_silent(1000 * kMs));
}

TEST(DeadReckoner, HandlesTickWrapAround) {
  const hal::Calibration cal;
  cs::DeadReckoner dr(cal, cs::DeadReckoningConfig{});
  Drive drive(dr, cal);
  drive.start_ticks = std::numeric_limits<std::int32_t>::max() - 1000;
  drive.v = [](double) { return 0.2; };  // 800 ticks/s: wraps after 1.25 s
  drive.run_until(0);
  dr.take_increment(0);
  drive.run_until(3000 * kMs);
  EXPECT_NEAR(dr.take_increment(3000 * kMs).dx_c.x(), 0.6, 1e-3);
  EXPECT_EQ(dr.counters().encoder_implausible, 0U);
}

TEST(DeadReckoner, RejectsBadSamplesByReason) {
  const hal::Calibration cal;
  cs::DeadReckoner dr(cal, cs::DeadReckoningConfig{});
  hal::GyroSample g;
  g.t_ns = 100 * kMs;
  EXPECT_TRUE(dr.add_gyro(g));
  EXPECT_FALSE(dr.add_gyro(g));  // duplicate
  g.t_ns = 50 * kMs;
  EXPECT_FALSE(dr.add_gyro(g));  // out of order
  g.t_ns = 110 * kMs;
  g.wz_rad_s = std::nan("");
  EXPECT_FALSE(dr.add_gyro(g));
  g.wz_rad_s = 1e3;
  EXPECT_FALSE(dr.add_gyro(g));
  g.wz_rad_s = 0.0;
  g.has_xy = true;
  g.wx_rad_s = INFINITY;
  EXPECT_FALSE(dr.add_gyro(g));
  const cs::DeadReckonerCounters& c = dr.counters();
  EXPECT_EQ(c.gyro_accepted, 1U);
  EXPECT_EQ(c.gyro_duplicate, 1U);
  EXPECT_EQ(c.gyro_out_of_order, 1U);
  EXPECT_EQ(c.gyro_non_finite, 2U);
  EXPECT_EQ(c.gyro_implausible, 1U);

  hal::EncoderSample e;
  e.t_ns = 100 * kMs;
  EXPECT_TRUE(dr.add_encoder(e));
  EXPECT_FALSE(dr.add_encoder(e));
  e.t_ns = 90 * kMs;
  EXPECT_FALSE(dr.add_encoder(e));
  e.t_ns = 150 * kMs;
  e.left_ticks = 100000;  // 25 m in 50 ms
  e.right_ticks = 100000;
  EXPECT_FALSE(dr.add_encoder(e));
  e.t_ns = 200 * kMs;
  e.left_ticks = 100040;  // 1 cm in 50 ms, counted from the re-anchored sample
  e.right_ticks = 100040;
  EXPECT_TRUE(dr.add_encoder(e));
  EXPECT_EQ(c.encoder_duplicate, 1U);
  EXPECT_EQ(c.encoder_out_of_order, 1U);
  EXPECT_EQ(c.encoder_implausible, 1U);
  EXPECT_NEAR(dr.x(), 0.01, 1e-9);
  const cs::OdometryIncrement u = dr.take_increment(200 * kMs);
  EXPECT_TRUE(u.dx_c.allFinite());
  EXPECT_TRUE(u.Q.allFinite());
  EXPECT_EQ(dr.take_increment(100 * kMs).distance_m, 0.0);
  EXPECT_EQ(c.increments_out_of_order, 1U);
}

TEST(DeadReckoner, DetectsStandingStillAndEstimatesBias) {
  const hal::Calibration cal;
  cs::DeadReckoner dr(cal, cs::DeadReckoningConfig{});
  Drive drive(dr, cal);
  drive.gyro_bias = 0.004;
  drive.gyro_noise = 0.002;
  drive.v = [](double t) { return t > 5.0 && t < 6.0 ? 0.2 : 0.0; };
  drive.run_until(300 * kMs);
  EXPECT_FALSE(dr.standing_still());  // not yet a full window
  drive.run_until(4000 * kMs);
  EXPECT_TRUE(dr.standing_still());
  EXPECT_NEAR(dr.gyro_bias(), 0.004, 5e-4);
  drive.run_until(5500 * kMs);
  EXPECT_FALSE(dr.standing_still());
  drive.run_until(7000 * kMs);
  EXPECT_TRUE(dr.standing_still());
  // With the bias removed, heading barely drifts over the still period.
  dr.take_increment(7000 * kMs);
  drive.run_until(9000 * kMs);
  EXPECT_LT(std::abs(dr.take_increment(9000 * kMs).dpsi_c.z()), 2e-3);
}

TEST(DeadReckoner, CameraIncrementJacobianMatchesNumeric) {
  // A camera tilted and offset from the body: the lever arm couples rotation into translation.
  const Eigen::Matrix3d R_bc = cs::rotation_zyx(0.05, -0.2, 0.1);
  const Eigen::Vector3d t_bc(0.1, -0.03, 0.08);
  cs::Vector6d body;
  body << 0.12, 0.02, 0.001, 0.01, -0.02, 0.7;
  cs::Matrix6d J;
  cs::camera_increment_from_body(body, R_bc, t_bc, &J);
  const auto f = [&](const cs::Vector6d& b) {
    return cs::camera_increment_from_body(b, R_bc, t_bc, nullptr);
  };
  EXPECT_LT((cleanslam::test::numeric_jacobian<6, 6>(f, body) - J).norm(), 1e-8);
  // Turning in place moves the camera on a circle around the wheel axis.
  cs::Vector6d turn = cs::Vector6d::Zero();
  turn(5) = std::acos(-1.0);
  const cs::Vector6d u =
      cs::camera_increment_from_body(turn, Eigen::Matrix3d::Identity(), t_bc, nullptr);
  EXPECT_NEAR(u(0), -0.2, 1e-12);
  EXPECT_NEAR(u(1), 0.06, 1e-12);
}

namespace {

cs::OdometryIncrement arc_increment(const hal::Calibration& cal, const cs::DeadReckoningConfig& c,
                                    double v, double w) {
  cs::DeadReckoner dr(cal, c);
  Drive drive(dr, cal);
  drive.v = [v](double) { return v; };
  drive.w = [w](double) { return w; };
  drive.run_until(0);
  dr.take_increment(0);
  drive.run_until(2000 * kMs);
  return dr.take_increment(2000 * kMs);
}

}  // namespace

TEST(DeadReckoner, PersistentErrorsInflateQByCorrelationTime) {
  const hal::Calibration cal;
  cs::DeadReckoningConfig plain = gyro_only();
  plain.z_noise_m_per_sqrt_m = 0.0;
  plain.roll_pitch_noise_rad_per_sqrt_m = 0.0;
  cs::DeadReckoningConfig persistent = plain;
  persistent.gyro_bias_correlation_time_s = 10.0;
  persistent.gyro_scale_error = 0.01;
  const double bi = cal.gyro.bias_instability;
  // Turning in place for 2 s at 0.4 rad/s: heading variance grows by bi^2 T dt + (s dyaw)^2.
  const cs::OdometryIncrement a = arc_increment(cal, plain, 0.0, 0.4);
  const cs::OdometryIncrement b = arc_increment(cal, persistent, 0.0, 0.4);
  EXPECT_NEAR(b.Q(5, 5) - a.Q(5, 5), bi * bi * 10.0 * 2.0 + 0.01 * 0.01 * 0.8 * 0.8, 1e-9);
  // Straight for 2 s at 0.25 m/s: neither touches the along-track variance.
  const cs::OdometryIncrement c = arc_increment(cal, plain, 0.25, 0.0);
  const cs::OdometryIncrement d = arc_increment(cal, persistent, 0.25, 0.0);
  EXPECT_NEAR(d.Q(0, 0), c.Q(0, 0), 1e-12);
  EXPECT_GT(cleanslam::test::min_eigenvalue(d.Q), -1e-15);
}

namespace {

// The increment of 2.03 s of driving with a gyro reading `offset` too high.
cs::OdometryIncrement increment_with_gyro_offset(const hal::Calibration& cal,
                                                 const cs::DeadReckoningConfig& c, double offset) {
  cs::DeadReckoner dr(cal, c);
  Drive drive(dr, cal);
  drive.v = [](double) { return 0.2; };
  drive.w = [](double t) { return 0.3 + 0.2 * std::sin(t); };
  drive.gyro_bias = offset;
  drive.run_until(0);
  dr.take_increment(0);
  drive.run_until(2030 * kMs);
  return dr.take_increment(2030 * kMs);
}

// A gyro reading b too high is a residual bias b: the true increment is u(b) + du/db b.
cs::Vector6d numeric_du_dbias(const hal::Calibration& cal, const cs::DeadReckoningConfig& c) {
  const auto f = [&](const Eigen::Matrix<double, 1, 1>& b) {
    const cs::OdometryIncrement ub = increment_with_gyro_offset(cal, c, b(0));
    cs::Vector6d out;
    out << ub.dx_c, ub.dpsi_c;
    return out;
  };
  return -cleanslam::test::numeric_jacobian<6, 1>(f, Eigen::Matrix<double, 1, 1>::Zero(), 1e-4);
}

}  // namespace

// Q's share of the gyro bias within the increment is bias_instability^2 du/db du/db^T, du/db the
// increment's numerical derivative by a gyro offset.
TEST(DeadReckoner, QsGyroBiasTermIsTheNumericalDerivativesOuterProduct) {
  hal::Calibration cal;
  cal.gyro.bias_instability = 0.0;
  const cs::DeadReckoningConfig c = gyro_only();
  const cs::OdometryIncrement without = increment_with_gyro_offset(cal, c, 0.0);
  const cs::Vector6d numeric = numeric_du_dbias(cal, c);
  cal.gyro.bias_instability = 0.01;
  const cs::OdometryIncrement with = increment_with_gyro_offset(cal, c, 0.0);
  const cs::Matrix6d expected = 0.01 * 0.01 * numeric * numeric.transpose();
  EXPECT_LT((with.Q - without.Q - expected).cwiseAbs().maxCoeff(), 1e-10)
      << (with.Q - without.Q) << "\n\n"
      << expected;
  EXPECT_GT(numeric.norm(), 1.0);
}

// Q's share of the distance scale is distance_noise^2 du/ds du/ds^T, du/ds the increment's
// numerical derivative by a wheel scale error.
TEST(DeadReckoner, QsDistanceScaleTermIsTheNumericalDerivativesOuterProduct) {
  hal::Calibration cal;
  const cs::DeadReckoningConfig c = gyro_only();
  // Wheels that count (1 + s) times the calibrated ticks per metre make the reckoner measure a
  // distance 1 + s times too short: the true increment is u(s) + du/ds s.
  const auto run = [&](double s, double distance_noise) {
    hal::Calibration believed = cal;
    believed.wheels.ticks_per_meter_left *= 1.0 + s;
    believed.wheels.ticks_per_meter_right *= 1.0 + s;
    believed.wheels.distance_noise = distance_noise;
    cs::DeadReckoner dr(believed, c);
    Drive drive(dr, cal);
    drive.v = [](double t) { return 0.2 + 0.05 * std::cos(t); };
    drive.w = [](double t) { return 0.3 + 0.2 * std::sin(t); };
    drive.run_until(0);
    dr.take_increment(0);
    drive.run_until(2030 * kMs);
    return dr.take_increment(2030 * kMs);
  };
  const auto f = [&](const Eigen::Matrix<double, 1, 1>& s) {
    const cs::OdometryIncrement us = run(s(0), 0.0);
    cs::Vector6d out;
    out << us.dx_c, us.dpsi_c;
    return out;
  };
  const cs::Vector6d numeric =
      -cleanslam::test::numeric_jacobian<6, 1>(f, Eigen::Matrix<double, 1, 1>::Zero(), 1e-4);
  const cs::Matrix6d delta = run(0.0, 0.05).Q - run(0.0, 0.0).Q;
  const cs::Matrix6d expected = 0.05 * 0.05 * numeric * numeric.transpose();
  EXPECT_LT((delta - expected).cwiseAbs().maxCoeff(), 1e-9) << delta << "\n\n" << expected;
  EXPECT_GT(numeric.head<3>().norm(), 0.3);
}

TEST(DeadReckoner, WheelYawFusionHoldsTheHeadingWhileTheWheelsStandStillAndLearnsTheBias) {
  // A noisy gyro whose calibration says so: its bias within the stated instability.
  hal::Calibration cal;
  cal.gyro.noise_density = 0.01;
  cal.gyro.bias_instability = 0.02;
  const auto still_then_turn = [&](const cs::DeadReckoningConfig& c, double& yaw_still,
                                   double& yaw_turned, double& bias) {
    cs::DeadReckoner dr(cal, c);
    Drive drive(dr, cal);
    drive.gyro_bias = 0.02;
    drive.gyro_noise = 0.1;  // per 100 Hz sample, far above standstill_rate_rad_s
    drive.w = [](double t) { return t > 60.0 ? 0.4 : 0.0; };
    drive.run_until(0);
    dr.take_increment(0);
    drive.run_until(60000 * kMs);
    yaw_still = dr.yaw();
    bias = dr.wheel_yaw_fusion().calibration()(0);
    drive.run_until(62000 * kMs);
    yaw_turned = dr.yaw() - yaw_still;
  };
  cs::DeadReckoningConfig fused = gyro_only();
  fused.wheel_yaw.enabled = true;
  double yaw_fused = 0.0;
  double turn_fused = 0.0;
  double bias_fused = 0.0;
  still_then_turn(fused, yaw_fused, turn_fused, bias_fused);
  double yaw_gyro = 0.0;
  double turn_gyro = 0.0;
  double bias_gyro = 0.0;
  still_then_turn(gyro_only(), yaw_gyro, turn_gyro, bias_gyro);
  // The gyro's own standstill test never passes through this noise: alone it integrates 60 s of
  // bias (1.2 rad). Wheels that do not turn hold the heading, and the fusion learns the bias
  // from them.
  EXPECT_LT(std::abs(yaw_fused), 0.05);
  EXPECT_GT(yaw_gyro, 1.0);
  EXPECT_NEAR(bias_fused, 0.02, 0.004);
  // Turning on the spot moves the wheels: the turn is the gyro's and the wheels'.
  EXPECT_NEAR(turn_fused, 0.84, 0.05);
  EXPECT_NEAR(turn_gyro, 0.84 + 2.0 * 0.02, 0.05);
}

TEST(DeadReckoner, WheelYawFusionHoldsTheHeadingBetterThanANoisyGyro) {
  hal::Calibration cal;
  cal.gyro.noise_density = 0.05;
  cal.gyro.bias_instability = 0.005;
  cal.wheels.distance_noise = 0.1;
  // RMS of the heading's error over 60 s windows of the last 10 minutes.
  const auto heading_change_rms = [&](bool fused) {
    cs::DeadReckoningConfig c;
    c.wheel_yaw.enabled = fused;
    cs::DeadReckoner dr(cal, c);
    Drive drive(dr, cal);
    drive.gyro_noise = 0.05 * 10.0;  // per 100 Hz sample
    drive.gyro_bias = 0.004;
    drive.left_scale = 1.06;
    drive.right_scale = 1.02;
    // Runs of 6 s straight ahead, then 3 s turning one way or the other.
    drive.v = [](double t) { return std::fmod(t, 9.0) < 6.0 ? 0.15 : 0.0; };
    drive.w = [](double t) {
      return std::fmod(t, 9.0) < 6.0 ? 0.0 : (std::fmod(t, 27.0) < 18.0 ? 0.3 : -0.3);
    };
    std::vector<double> err;
    for (int s = 0; s <= 900; ++s) {
      drive.run_until(static_cast<hal::TimeNs>(s) * 1000 * kMs);
      err.push_back(cs::wrap_angle(dr.yaw() - drive.yaw));
    }
    double sum2 = 0.0;
    int n = 0;
    for (std::size_t s = 300; s + 60 < err.size(); s += 10) {
      const double e = cs::wrap_angle(err[s + 60] - err[s]);
      sum2 += e * e;
      ++n;
    }
    if (fused) {
      EXPECT_GT(dr.wheel_yaw_fusion().counters().windows_used, 300U);
      EXPECT_EQ(dr.wheel_yaw_fusion().counters().intervals_rejected, 0U);
    }
    return std::sqrt(sum2 / n);
  };
  const double gyro = heading_change_rms(false);
  const double fused = heading_change_rms(true);
  std::printf("60 s heading change error: gyro %.3f rad, gyro and wheels %.3f rad\n", gyro, fused);
  EXPECT_LT(fused, 0.7 * gyro);
}

// A sample the plausibility check refuses costs its interval's wheel motion, never the gyro's
// heading: stamped before the end of a take that extrapolated past the last good sample, and after.
TEST(DeadReckoner, AnImplausibleEncoderSampleLosesNoHeading) {
  for (const hal::TimeNs jump_t : {1520 * kMs, 1540 * kMs}) {
    const hal::Calibration cal;
    cs::DeadReckoner dr(cal, cs::DeadReckoningConfig{});
    Drive drive(dr, cal);
    drive.v = [](double) { return 0.2; };
    drive.w = [](double) { return 0.5; };
    drive.run_until(0);
    dr.take_increment(0);
    drive.run_until(1530 * kMs);  // the last good sample at 1.5 s: the take extrapolates
    double yaw_sum = dr.take_increment(1530 * kMs).dpsi_c.z();
    drive.run_until(jump_t);
    hal::EncoderSample jump;
    jump.t_ns = jump_t;
    jump.left_ticks = 1 << 30;
    jump.right_ticks = -(1 << 30);
    EXPECT_FALSE(dr.add_encoder(jump));
    EXPECT_EQ(dr.counters().encoder_implausible, 1U);
    for (hal::TimeNs t : {2010 * kMs, 2600 * kMs, 3000 * kMs}) {
      drive.run_until(t);
      yaw_sum += dr.take_increment(t).dpsi_c.z();
    }
    EXPECT_NEAR(yaw_sum, drive.yaw, 1e-3) << "implausible sample at " << jump_t / kMs << " ms";
  }
}
