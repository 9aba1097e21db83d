#include <cmath>

#include <gtest/gtest.h>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/slam_estimator.hpp"

// filter.gyro_errors_from_calibration: the calibration's gyro.scale_error and gyro.bias_walk reach
// the prediction when they exceed the filter's own values.
namespace firmware = cleanslam::firmware;
namespace hal = cleanslam::hal;

namespace {

constexpr hal::TimeNs kMs = hal::kNsPerMillisecond;
constexpr double kRate = 1.0;  // rad/s, turning on the spot

firmware::FirmwareConfig config(bool from_calibration) {
  firmware::FirmwareConfig c;
  c.calibration.gyro.scale_error = 0.05;
  c.calibration.gyro.bias_walk = 0.01;
  c.slam.odometry.gyro_scale_error = 0.005;
  c.slam.filter.gyro_bias_state = true;
  c.slam.filter.gyro_bias_walk = 0.001;
  c.gyro_errors_from_calibration = from_calibration;
  return c;
}

struct Turn {
  double yaw_variance = 0.0;
  double bias_variance = 0.0;
};

// Two seconds turning left at kRate (wheels counter-rotating), a prediction after each second (the
// first has no time step for the bias walk).
Turn turn(const firmware::FirmwareConfig& c) {
  firmware::SlamEstimator e(c);
  e.reset(0);
  const double ticks_per_rad = 4000.0 * 0.5 * 0.235;
  for (hal::TimeNs t = 0; t <= 2000 * kMs; t += 10 * kMs) {
    hal::GyroSample g;
    g.t_ns = t;
    g.wz_rad_s = kRate;
    e.add_gyro(g);
    if (t % (50 * kMs) == 0) {
      const auto ticks =
          static_cast<std::int32_t>(std::llround(kRate * hal::to_seconds(t) * ticks_per_rad));
      hal::EncoderSample s;
      s.t_ns = t;
      s.left_ticks = -ticks;
      s.right_ticks = ticks;
      e.add_encoder(s);
    }
    if (t == 1000 * kMs) e.predict(t, true);
  }
  e.predict(2000 * kMs, true);
  return Turn{e.pose(2000 * kMs).covariance[35], e.ekf().gyro_bias_variance()};
}

}  // namespace

TEST(SlamEstimatorGyroErrors, TheCalibrationsScaleErrorAndBiasWalkWidenThePrediction) {
  const Turn off = turn(config(false));
  const Turn on = turn(config(true));
  ASSERT_TRUE(std::isfinite(off.yaw_variance) && std::isfinite(on.yaw_variance));
  // At least (0.05^2 - 0.005^2) * (1 rad)^2 more heading variance per prediction from the scale.
  const double scale_gain = (0.05 * 0.05 - 0.005 * 0.005) * 2.0;
  EXPECT_GT(on.yaw_variance - off.yaw_variance, 0.8 * scale_gain);
  // The bias walk: (0.01^2 - 0.001^2) * 1 s more bias variance.
  const double walk_gain = 0.01 * 0.01 - 0.001 * 0.001;
  EXPECT_NEAR(on.bias_variance - off.bias_variance, walk_gain, 0.2 * walk_gain);
}

TEST(SlamEstimatorGyroErrors, TheFiltersLargerValuesStayWhenTheCalibrationStatesNone) {
  firmware::FirmwareConfig c = config(true);
  c.calibration.gyro.scale_error = 0.0;
  c.calibration.gyro.bias_walk = 0.0;
  const Turn on = turn(c);
  c.gyro_errors_from_calibration = false;
  const Turn off = turn(c);
  EXPECT_GT(off.bias_variance, 0.0);
  EXPECT_EQ(on.yaw_variance, off.yaw_variance);
  EXPECT_EQ(on.bias_variance, off.bias_variance);
}
