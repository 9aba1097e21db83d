#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "cleanslam/firmware/estimator.hpp"
#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/hal/interfaces.hpp"
#include "time_units.hpp"

namespace cleanslam::test {

// A sensor-silence predicate for ScriptedSource::drive that never silences a sensor.
inline auto never_silent() {
  return [](hal::SensorEvent::Kind, hal::TimeNs) { return false; };
}

// A scripted virtual-time source: events in the given order, each due at `due` (the event's own
// stamp unless a test wants a lie).
class ScriptedSource final : public hal::SensorSource {
 public:
  struct Item {
    hal::TimeNs due;
    hal::SensorEvent ev;
  };
  std::vector<Item> items;
  std::vector<std::vector<hal::FeatureObservation>> features;  // kept alive for frame items
  std::size_t next = 0;

  [[nodiscard]] hal::TimeNs next_event_time() const override {
    return next < items.size() ? items[next].due : -1;
  }
  bool read(hal::SensorEvent& out) override {
    if (next >= items.size()) {
      return false;
    }
    out = items[next++].ev;
    return true;
  }
  [[nodiscard]] bool exhausted() const override { return next >= items.size(); }

  void gyro(hal::TimeNs t, double wz) {
    hal::SensorEvent ev;
    ev.kind = hal::SensorEvent::Kind::kGyro;
    ev.gyro.t_ns = t;
    ev.gyro.wz_rad_s = wz;
    items.push_back({t, ev});
  }
  void encoder(hal::TimeNs t, std::int32_t left, std::int32_t right) {
    hal::SensorEvent ev;
    ev.kind = hal::SensorEvent::Kind::kEncoder;
    ev.encoder.t_ns = t;
    ev.encoder.left_ticks = left;
    ev.encoder.right_ticks = right;
    items.push_back({t, ev});
  }
  void frame(hal::TimeNs t, int n_features) {
    features.reserve(1024);
    std::vector<hal::FeatureObservation> f;
    for (int i = 0; i < n_features; ++i) {
      f.push_back({i, 100.0 + i + static_cast<double>(t % 1000) * 1e-3, 50.0 + 2.0 * i});
    }
    features.push_back(std::move(f));
    hal::SensorEvent ev;
    ev.kind = hal::SensorEvent::Kind::kFrame;
    ev.frame.t_ns = t;
    ev.frame.features = features.back().data();
    ev.frame.feature_count = n_features;
    items.push_back({t, ev});
  }
  // A robot driving: gyro 100 Hz, encoders 20 Hz, frames at frame_hz, in [t0, t1), skipping
  // what the predicates say is silent.
  template <typename Silent>
  void drive(hal::TimeNs t0, hal::TimeNs t1, double frame_hz, Silent silent) {
    const hal::TimeNs frame_period = static_cast<hal::TimeNs>(1e9 / frame_hz);
    for (hal::TimeNs t = t0; t < t1; t += 10'000'000) {
      if (!silent(hal::SensorEvent::Kind::kGyro, t)) {
        gyro(t, 0.1);
      }
      if ((t - t0) % 50'000'000 == 0 && !silent(hal::SensorEvent::Kind::kEncoder, t)) {
        const auto k = static_cast<std::int32_t>(t / 50'000'000);
        encoder(t, 40 * k, 44 * k);
      }
      if ((t - t0) % frame_period == 0 && !silent(hal::SensorEvent::Kind::kFrame, t)) {
        frame(t, 6);
      }
    }
  }
};

// A deterministic toy estimator: integrates the gyro and the wheels, one work unit per feature.
class FakeEstimator final : public firmware::Estimator {
 public:
  double yaw = 0.0;
  double distance = 0.0;
  std::int32_t last_left = 0;
  bool have_encoder = false;
  hal::TimeNs last_gyro = -1;
  int predictions = 0;
  int frames_begun = 0;
  int resets = 0;
  hal::CameraFrame frame;
  int remaining = 0;
  std::vector<hal::log::UpdateRecord> records;
  bool still = false;
  bool lost = false;

  [[nodiscard]] bool pose_lost() const override { return lost; }
  void reset(hal::TimeNs /*t*/) override {
    ++resets;
    records.reserve(hal::kMaxFeaturesPerFrame);
  }
  void add_gyro(const hal::GyroSample& s) override {
    if (last_gyro >= 0) {
      yaw += s.wz_rad_s * hal::to_seconds(s.t_ns - last_gyro);
    }
    last_gyro = s.t_ns;
  }
  void add_encoder(const hal::EncoderSample& s) override {
    if (have_encoder) {
      distance += hal::tick_delta(s.left_ticks, last_left) * 2.5e-4;
    }
    last_left = s.left_ticks;
    have_encoder = true;
  }
  void predict(hal::TimeNs /*t*/) override { ++predictions; }
  void begin_frame(const hal::CameraFrame& f) override {
    frame = f;
    remaining = f.feature_count;
    records.clear();
    ++frames_begun;
  }
  bool step_frame(int& budget) override {
    while (remaining > 0 && budget > 0) {
      const int i = frame.feature_count - remaining;
      hal::log::UpdateRecord r;
      r.t_ns = frame.t_ns;
      r.track_id = frame.features[i].track_id;
      r.slot = i;
      r.status = hal::log::UpdateStatus::kUpdated;
      r.u_px = frame.features[i].u_px;
      r.v_px = frame.features[i].v_px;
      r.innovation_u = std::sin(yaw + i);
      r.mahalanobis2 = distance * 0.5;
      records.push_back(r);
      yaw += 1e-4 * r.innovation_u;
      --remaining;
      --budget;
    }
    return remaining == 0;
  }
  int update_records(const hal::log::UpdateRecord*& out) const override {
    out = records.data();
    return static_cast<int>(records.size());
  }
  [[nodiscard]] hal::PoseEstimate pose(hal::TimeNs t) const override {
    hal::PoseEstimate p;
    p.t_ns = t;
    p.position_m = {distance * std::cos(yaw), distance * std::sin(yaw), 0.0};
    p.orientation_wxyz = {std::cos(yaw / 2), 0.0, 0.0, std::sin(yaw / 2)};
    p.covariance[0] = 1e-3 * distance;
    return p;
  }
  [[nodiscard]] bool standing_still() const override { return still; }
  [[nodiscard]] hal::PoseEstimate dead_reckoning_pose(hal::TimeNs t) const override {
    hal::PoseEstimate p;
    p.t_ns = t;
    p.position_m = {distance, 0.0, 0.0};
    return p;
  }
  int landmarks(firmware::LandmarkEstimate* out, int max) const override {
    if (max > 0) {
      out[0].slot = 0;
      out[0].position_m = {distance, 1.0, 0.0};
    }
    return max > 0 ? 1 : 0;
  }
};

class CollectingSink final : public hal::PoseSink {
 public:
  std::vector<hal::PoseEstimate> poses;
  int flushes = 0;
  CollectingSink() { poses.reserve(100000); }
  void publish(const hal::PoseEstimate& p) override { poses.push_back(p); }
  void flush() override { ++flushes; }
};

}  // namespace cleanslam::test
