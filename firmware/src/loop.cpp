#include "cleanslam/firmware/loop.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace cleanslam::firmware {

namespace {
constexpr int kMaxEventsPerSourceAndIteration = 64;
static_assert(kRejectCount <= 32, "Loop::told_ has a bit per reason");

hal::TimeNs period_ns(double rate_hz) {
  return static_cast<hal::TimeNs>(std::llround(1e9 / rate_hz));
}
}  // namespace

Loop::Loop(const LoopOptions& options, Estimator& estimator)
    : options_(options), estimator_(estimator) {
  publish_period_ns_ = period_ns(options_.publish_rate_hz);
  frame_period_ns_ = period_ns(options_.frame_rate_hz);
  sources_.reserve(8);
  pose_sinks_.reserve(8);
  update_sinks_.reserve(8);
  gyro_sinks_.reserve(8);
  frame_sinks_.reserve(4);
  frame_dr_sinks_.reserve(4);
}

void Loop::add_source(hal::SensorSource* source) {
  sources_.push_back(source);
}
void Loop::add_pose_sink(hal::PoseSink* sink) {
  pose_sinks_.push_back(sink);
}
void Loop::add_update_sink(UpdateSink* sink) {
  update_sinks_.push_back(sink);
}

void Loop::add_gyro_sink(GyroSink* sink) {
  gyro_sinks_.push_back(sink);
}
void Loop::add_frame_sinks(hal::PoseSink* estimate, hal::PoseSink* dead_reckoning) {
  if (estimate != nullptr) {
    frame_sinks_.push_back(estimate);
  }
  if (dead_reckoning != nullptr) {
    frame_dr_sinks_.push_back(dead_reckoning);
  }
}

void Loop::count(Reject r, std::uint64_t n, bool told) {
  if (n == 0) {
    return;
  }
  stats_.rejects.add(r, n);
  rejected_since_publish_ = true;
  const std::uint32_t bit = 1U << static_cast<unsigned>(r);
  if (!told && (told_ & bit) == 0) {
    told_ |= bit;
    if (observer_ != nullptr) {
      observer_->first_reject(now_ns_, r);
    }
  }
}

void Loop::start(hal::TimeNs now) {
  start_ns_ = now;
  now_ns_ = now;
  next_publish_ns_ = hal::add_saturated(now, publish_period_ns_);
  if (recorder_ != nullptr) {
    recorder_->clock(now);
  }
  estimator_.reset(now);
  if (notifier_ != nullptr) {
    notifier_->ready();
    if (notifier_->watchdog_period_ns() > 0) {
      next_watchdog_ns_ = now;
    }
  }
}

void Loop::iterate(hal::TimeNs now) {
  ++stats_.iterations;
  now_ns_ = now;
  if (recorder_ != nullptr) {
    recorder_->clock(now);
  }
  hal::SensorEvent ev;
  for (hal::SensorSource* src : sources_) {
    for (int k = 0; k < kMaxEventsPerSourceAndIteration; ++k) {
      const hal::TimeNs due = src->next_event_time();
      const bool implausible = due > span_end();
      if ((due > now && !implausible) || !src->read(ev)) {
        break;
      }
      if (implausible) {
        count(Reject::kTimeJump);  // never due within the run: taken out so it blocks nothing
        continue;
      }
      ingest(ev, now);
    }
  }
  update_health(now);
  run_dead_reckoning();
  run_frame_steps();
  if (now >= next_publish_ns_) {
    publish(now);
    const hal::TimeNs behind = hal::sub_saturated(now, next_publish_ns_);
    next_publish_ns_ = hal::add_saturated(
        next_publish_ns_,
        hal::add_saturated(behind - behind % publish_period_ns_, publish_period_ns_));
  }
  if (notifier_ != nullptr && next_watchdog_ns_ >= 0 && now >= next_watchdog_ns_) {
    notifier_->watchdog();
    next_watchdog_ns_ = hal::add_saturated(now, notifier_->watchdog_period_ns());
  }
  if (recorder_ != nullptr) {
    const std::uint64_t dropped = recorder_->stats().dropped_buffer_full;
    count(Reject::kRecorderDropped, dropped - recorder_dropped_seen_);
    recorder_dropped_seen_ = dropped;
    recorder_->write_some();
  }
}

hal::TimeNs Loop::next_deadline() const {
  if (frame_work_pending()) {
    return std::numeric_limits<hal::TimeNs>::min();
  }
  hal::TimeNs d = next_publish_ns_;
  const auto silence = [&](hal::TimeNs last, hal::TimeNs timeout, std::uint32_t flag) {
    if ((health_ & flag) == 0) {
      d = std::min(d, hal::add_saturated(last >= 0 ? last : start_ns_, timeout + 1));
    }
  };
  silence(last_gyro_ns_, options_.gyro_timeout_ns, hal::kGyroSilent);
  silence(last_encoder_ns_, options_.encoder_timeout_ns, hal::kEncodersSilent);
  silence(last_frame_ns_, options_.camera_timeout_ns, hal::kCameraSilent);
  if (notifier_ != nullptr && next_watchdog_ns_ >= 0) {
    d = std::min(d, next_watchdog_ns_);
  }
  return d;
}

bool Loop::check_time(hal::TimeNs t, hal::TimeNs last, hal::TimeNs now) {
  if (last >= 0 && t <= last) {
    count(Reject::kOutOfOrder);
    return false;
  }
  if (t > hal::add_saturated(now, options_.max_lead_ns) ||
      t < hal::sub_saturated(now, options_.max_time_skew_ns) || t > span_end()) {
    count(Reject::kTimeJump);
    return false;
  }
  return true;
}

void Loop::ingest(const hal::SensorEvent& ev, hal::TimeNs now) {
  switch (ev.kind) {
    case hal::SensorEvent::Kind::kGyro:
      ingest_gyro(ev.gyro, now);
      break;
    case hal::SensorEvent::Kind::kEncoder:
      ingest_encoder(ev.encoder, now);
      break;
    case hal::SensorEvent::Kind::kFrame:
      ingest_frame(ev.frame, now);
      break;
    case hal::SensorEvent::Kind::kLift:
      if (recorder_ != nullptr) {
        recorder_->lift(now, ev.lifted);
      }
      if (lifted_ && !ev.lifted) {
        estimator_.set_down(now);  // a new map or relocalization (map_management.on_set_down)
      }
      lifted_ = ev.lifted;
      if (lifted_) {
        active_ = nullptr;
        pending_ = nullptr;
      }
      break;
    case hal::SensorEvent::Kind::kNone:
      break;
  }
}

void Loop::ingest_gyro(const hal::GyroSample& s, hal::TimeNs now) {
  ++stats_.gyro;
  if (recorder_ != nullptr) {
    recorder_->gyro(s);
  }
  if (!std::isfinite(s.wz_rad_s) ||
      (s.has_xy && (!std::isfinite(s.wx_rad_s) || !std::isfinite(s.wy_rad_s)))) {
    count(Reject::kNonFinite);
    return;
  }
  if (!check_time(s.t_ns, last_gyro_ns_, now)) {
    return;
  }
  last_gyro_ns_ = s.t_ns;
  estimator_.add_gyro(s);
  for (GyroSink* sink : gyro_sinks_) {
    sink->gyro(s);
  }
}

void Loop::ingest_encoder(const hal::EncoderSample& s, hal::TimeNs now) {
  ++stats_.encoders;
  if (recorder_ != nullptr) {
    recorder_->encoder(s);
  }
  if (!check_time(s.t_ns, last_encoder_ns_, now)) {
    return;
  }
  last_encoder_ns_ = s.t_ns;
  estimator_.add_encoder(s);
  odometry_pending_ = true;
}

void Loop::ingest_frame(const hal::CameraFrame& f, hal::TimeNs now) {
  ++stats_.frames_in;
  if (recorder_ != nullptr) {
    recorder_->frame(f);
  }
  if (!check_time(f.t_ns, last_frame_ns_, now)) {
    return;
  }
  last_frame_ns_ = f.t_ns;
  const bool image = f.has_image();
  if ((!image && !f.has_features()) ||
      (image && (f.image.width > hal::kImageWidth || f.image.height > hal::kImageHeight))) {
    count(Reject::kBadFrame);
    return;
  }
  if (image &&
      (f.image.width != options_.camera.width || f.image.height != options_.camera.height)) {
    count(Reject::kImageSize);
    return;
  }
  if (lifted_) {
    return;
  }
  if (last_accepted_frame_ns_ >= 0 && hal::sub_saturated(f.t_ns, last_accepted_frame_ns_) <
                                          frame_period_ns_ - frame_period_ns_ / 10) {
    count(Reject::kFrameRate);
    return;
  }
  FrameSlot* slot = pending_;
  if (slot != nullptr) {
    count(Reject::kFrameSuperseded);
  } else {
    slot = active_ == &slots_[0] ? &slots_[1] : &slots_[0];
  }
  hal::CameraFrame& out = slot->frame;
  out = hal::CameraFrame{};
  out.t_ns = f.t_ns;
  out.seq = f.seq;
  if (image) {
    for (int y = 0; y < f.image.height; ++y) {
      std::memcpy(slot->pixels.data() +
                      static_cast<std::size_t>(y) * static_cast<std::size_t>(f.image.width),
                  f.image.row(y), static_cast<std::size_t>(f.image.width));
    }
    out.image =
        hal::GrayImageView{slot->pixels.data(), f.image.width, f.image.height, f.image.width};
  }
  int n = 0;
  for (int i = 0; i < f.feature_count && f.features != nullptr; ++i) {
    const hal::FeatureObservation& o = f.features[i];
    if (!std::isfinite(o.u_px) || !std::isfinite(o.v_px) || o.track_id < 0 ||
        n >= hal::kMaxFeaturesPerFrame) {
      count(Reject::kBadFeature);
      continue;
    }
    slot->features[static_cast<std::size_t>(n++)] = o;
  }
  out.features = n > 0 ? slot->features.data() : nullptr;
  out.feature_count = n;
  if (!out.has_image() && !out.has_features()) {
    count(Reject::kBadFrame);
    return;
  }
  pending_ = slot;
  last_accepted_frame_ns_ = f.t_ns;
}

void Loop::run_dead_reckoning() {
  if (!odometry_pending_ && (health_ & hal::kEncodersSilent) != 0 && !lifted_ &&
      now_ns_ >= next_publish_ns_) {
    // Encoders silent: the estimate goes on from the gyro and the motion model, predicted at
    // each estimate published.
    const bool gyro_ok = (health_ & hal::kGyroSilent) == 0;
    estimator_.predict(gyro_ok ? last_gyro_ns_ : now_ns_);
    ++stats_.predictions;
    return;
  }
  if (!odometry_pending_) {
    return;
  }
  odometry_pending_ = false;
  estimator_.predict(last_encoder_ns_);
  ++stats_.predictions;
}

void Loop::run_frame_steps() {
  if (active_ == nullptr && pending_ != nullptr) {
    active_ = pending_;
    pending_ = nullptr;
    estimator_.begin_frame(active_->frame);
  }
  if (active_ == nullptr) {
    return;
  }
  int budget = options_.frame_work_budget;
  if (!estimator_.step_frame(budget)) {
    return;
  }
  const hal::log::UpdateRecord* records = nullptr;
  const int n = estimator_.update_records(records);
  for (int i = 0; i < n; ++i) {
    const auto status = static_cast<std::size_t>(records[i].status);
    if (status < stats_.records_by_status.size()) {
      ++stats_.records_by_status[status];
    }
    for (UpdateSink* sink : update_sinks_) {
      sink->update(records[i]);
    }
    if (recorder_ != nullptr) {
      recorder_->update(records[i]);
    }
  }
  stats_.update_records += static_cast<std::uint64_t>(n);
  ++stats_.frames_done;
  const hal::TimeNs t = active_->frame.t_ns;
  if (!frame_sinks_.empty()) {
    hal::PoseEstimate p = estimator_.pose(t);
    p.health |= health_;
    for (hal::PoseSink* sink : frame_sinks_) {
      sink->publish(p);
    }
  }
  if (!frame_dr_sinks_.empty()) {
    const hal::PoseEstimate p = estimator_.dead_reckoning_pose(t);
    for (hal::PoseSink* sink : frame_dr_sinks_) {
      sink->publish(p);
    }
  }
  active_ = nullptr;
}

void Loop::publish(hal::TimeNs now) {
  hal::PoseEstimate p = estimator_.pose(now);
  p.health |= health_;
  if (rejected_since_publish_) {
    p.health |= hal::kInputRejected;
    rejected_since_publish_ = false;
  }
  for (hal::PoseSink* sink : pose_sinks_) {
    sink->publish(p);
  }
  if (recorder_ != nullptr) {
    recorder_->pose(p);
  }
  ++stats_.poses;
}

void Loop::update_health(hal::TimeNs now) {
  const auto silent = [&](hal::TimeNs last, hal::TimeNs timeout) {
    return hal::sub_saturated(now, last >= 0 ? last : start_ns_) > timeout;
  };
  std::uint32_t h = hal::kHealthOk;
  if (silent(last_gyro_ns_, options_.gyro_timeout_ns)) {
    h |= hal::kGyroSilent;
  }
  if (silent(last_encoder_ns_, options_.encoder_timeout_ns)) {
    h |= hal::kEncodersSilent;
  }
  if (silent(last_frame_ns_, options_.camera_timeout_ns)) {
    h |= hal::kCameraSilent;
  }
  if (estimator_.standing_still()) {
    h |= hal::kStandingStill;
  }
  if (lifted_) {
    h |= hal::kLifted | hal::kPoseLost;
  }
  if (estimator_.pose_lost()) {
    h |= hal::kPoseLost;
  }
  if (h != health_) {
    if (observer_ != nullptr) {
      observer_->health_changed(now, health_, h);
    }
    health_ = h;
  }
}

void Loop::finish() {
  for (hal::PoseSink* sink : pose_sinks_) {
    sink->flush();
  }
  for (UpdateSink* sink : update_sinks_) {
    sink->flush();
  }
  for (hal::PoseSink* sink : frame_sinks_) {
    sink->flush();
  }
  for (hal::PoseSink* sink : frame_dr_sinks_) {
    sink->flush();
  }
  if (recorder_ != nullptr) {
    recorder_->flush(true);
  }
  if (notifier_ != nullptr) {
    notifier_->stopping();
  }
}

}  // namespace cleanslam::firmware
