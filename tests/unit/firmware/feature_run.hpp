#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/slam_estimator.hpp"
#include "time_units.hpp"

// A SlamEstimator driven straight ahead (gyro at 100 Hz, encoders at 20 Hz, 4000 ticks/m) and
// given feature frames; for the features-path tests.
namespace cleanslam::test {

struct FeatureRun {
  FeatureRun(const firmware::FirmwareConfig& config, double speed_m_s)
      : estimator(config), speed_m_s_(speed_m_s) {
    estimator.reset(0);
  }

  void drive_to(hal::TimeNs t) {
    for (; t_ <= t; t_ += 10 * kMs) {
      hal::GyroSample g;
      g.t_ns = t_;
      estimator.add_gyro(g);
      if (t_ % (50 * kMs) == 0) {
        hal::EncoderSample e;
        e.t_ns = t_;
        e.left_ticks =
            static_cast<std::int32_t>(std::llround(hal::to_seconds(t_) * speed_m_s_ * 4000.0));
        e.right_ticks = e.left_ticks;
        estimator.add_encoder(e);
      }
    }
  }

  // The frame's update records.
  std::vector<hal::log::UpdateRecord> frame(hal::TimeNs t,
                                            std::vector<hal::FeatureObservation> features) {
    drive_to(t);
    estimator.predict(t);
    hal::CameraFrame f;
    f.t_ns = t;
    f.features = features.data();
    f.feature_count = static_cast<int>(features.size());
    estimator.begin_frame(f);
    int budget = 1000;
    while (!estimator.step_frame(budget)) {
      budget = 1000;
    }
    const hal::log::UpdateRecord* records = nullptr;
    const int n = estimator.update_records(records);
    return {records, records + n};
  }

  firmware::SlamEstimator estimator;

 private:
  double speed_m_s_;
  hal::TimeNs t_ = 0;
};

}  // namespace cleanslam::test
