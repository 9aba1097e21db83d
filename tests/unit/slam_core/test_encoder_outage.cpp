#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

#include "cleanslam/slam_core/dead_reckoner.hpp"
#include "time_units.hpp"

namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

using cleanslam::test::kMs;

// Straight ahead at speed_m_s: gyro (zero rate) every 10 ms, encoders every 50 ms unless silent.
struct StraightDrive {
  cs::DeadReckoner& dr;
  const hal::Calibration& cal;
  double speed_m_s = 0.2;
  hal::TimeNs t = 0;
  void run_until(hal::TimeNs end, bool encoders, bool gyro = true) {
    for (; t <= end; t += 10 * kMs) {
      if (gyro) {
        hal::GyroSample g;
        g.t_ns = t;
        dr.add_gyro(g);
      }
      if (encoders && t % (50 * kMs) == 0) {
        hal::EncoderSample e;
        e.t_ns = t;
        const double d = speed_m_s * hal::to_seconds(t);
        e.left_ticks = static_cast<std::int32_t>(std::llround(d * cal.wheels.ticks_per_meter_left));
        e.right_ticks =
            static_cast<std::int32_t>(std::llround(d * cal.wheels.ticks_per_meter_right));
        dr.add_encoder(e);
      }
    }
  }
};

struct Sums {
  double distance = 0.0;
  double position_var = 0.0;
  double yaw_var = 0.0;
};

Sums take_every_half_second(cs::DeadReckoner& dr, StraightDrive& drive, hal::TimeNs from,
                            hal::TimeNs to, bool encoders, bool gyro = true) {
  Sums s;
  for (hal::TimeNs t = from; t <= to; t += 500 * kMs) {
    drive.run_until(t, encoders, gyro);
    const cs::OdometryIncrement u = dr.take_increment(t);
    s.distance += u.dx_c.norm();
    s.position_var += u.Q.topLeftCorner<3, 3>().trace();
    s.yaw_var += u.Q.bottomRightCorner<3, 3>().trace();
  }
  return s;
}

}  // namespace

// The last speed holds; the distance's variance is a stationary Ornstein-Uhlenbeck speed error's,
// from max_extrapolation_s past the last encoder sample.
TEST(EncoderOutage, TheSpeedHoldsAndTheDistanceVarianceGrows) {
  const hal::Calibration cal;
  const cs::DeadReckoningConfig config;
  cs::DeadReckoner dr(cal, config);
  StraightDrive drive{dr, cal};
  take_every_half_second(dr, drive, 0, 2000 * kMs, true);
  EXPECT_FALSE(dr.coasting());
  const Sums s = take_every_half_second(dr, drive, 2500 * kMs, 12000 * kMs, false);
  EXPECT_TRUE(dr.coasting());
  EXPECT_FALSE(dr.standing_still());
  const double tau = config.outage_speed_time_constant_s;
  const double coast_s = 10.0 - config.max_extrapolation_s;
  EXPECT_NEAR(s.distance, 0.2 * 10.0, 2e-3);
  const double sv = config.outage_speed_std_m_s;
  const double x = coast_s / tau;
  const double var = 2.0 * sv * sv * tau * tau * (x - 1.0 + std::exp(-x));
  EXPECT_GT(s.position_var, var);
  EXPECT_LT(s.position_var, 1.1 * var);
  // With the gyro the heading's variance stays small.
  EXPECT_LT(s.yaw_var, 1e-3);
}

// A frame stamped ahead of all sensors (camera time offset) is extrapolated, not an outage: the
// next encoder sample's interval counts.
TEST(EncoderOutage, AFrameAheadOfTheSensorsIsNoOutage) {
  const hal::Calibration cal;
  cs::DeadReckoner dr(cal, cs::DeadReckoningConfig{});
  StraightDrive drive{dr, cal};
  take_every_half_second(dr, drive, 0, 2000 * kMs, true);
  double distance = 0.0;
  for (hal::TimeNs t = 2500 * kMs; t <= 6000 * kMs; t += 500 * kMs) {
    drive.run_until(t, true);
    distance += dr.take_increment(t + 800 * kMs).dx_c.norm();
    EXPECT_FALSE(dr.coasting());
  }
  EXPECT_EQ(dr.counters().encoder_outages, 0U);
  drive.run_until(7000 * kMs, true);
  distance += dr.take_increment(7000 * kMs).dx_c.norm();
  EXPECT_NEAR(distance, 0.2 * 5.0, 0.01);
}

// The first encoder sample after the outage starts the count again: the ticks counted during the
// outage are not added on top of the model's distance.
TEST(EncoderOutage, ReturningEncodersStartTheCountAgain) {
  const hal::Calibration cal;
  cs::DeadReckoner dr(cal, cs::DeadReckoningConfig{});
  StraightDrive drive{dr, cal};
  take_every_half_second(dr, drive, 0, 2000 * kMs, true);
  take_every_half_second(dr, drive, 2500 * kMs, 12000 * kMs, false);
  EXPECT_EQ(dr.counters().encoder_outages, 0U);
  const Sums after = take_every_half_second(dr, drive, 12500 * kMs, 15000 * kMs, true);
  EXPECT_EQ(dr.counters().encoder_outages, 1U);
  EXPECT_FALSE(dr.coasting());
  // 12.0 .. 12.5 s: the model's last bit up to the sample at 12.01 s, then 0.2 m/s again.
  EXPECT_NEAR(after.distance, 0.2 * 3.0, 0.02);
}
