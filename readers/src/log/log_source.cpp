#include "cleanslam/readers/log_source.hpp"

namespace cleanslam::readers {

namespace lf = hal::log;

LogSource::LogSource(const LogReader& reader, Pacing pacing) : reader_(reader), pacing_(pacing) {
  if (pacing_ == Pacing::kEventTime) {
    skip_to_input();
  } else {
    const auto& recs = reader_.records();
    while (next_tick_ < recs.size() && recs[next_tick_].type != lf::RecordType::kClock) {
      ++next_tick_;
    }
    next_ = next_tick_;
  }
}

void LogSource::skip_to_input() {
  const auto& recs = reader_.records();
  while (next_ < recs.size() && !lf::is_input(recs[next_].type)) {
    ++next_;
  }
}

hal::TimeNs LogSource::event_time(const LogRecordRef& r) const {
  lf::ByteReader p = reader_.payload(r);
  return p.i64();  // every input payload starts with its time stamp
}

hal::TimeNs LogSource::next_event_time() const {
  const auto& recs = reader_.records();
  if (pacing_ == Pacing::kEventTime) {
    return next_ < recs.size() ? event_time(recs[next_]) : -1;
  }
  return -1;  // released events are ready now, like a live device's
}

bool LogSource::tick_has_input() const {
  const auto& recs = reader_.records();
  for (std::size_t i = next_; in_tick_ && i < next_tick_ && i < recs.size(); ++i) {
    if (lf::is_input(recs[i].type)) {
      return true;
    }
  }
  return false;
}

hal::TimeNs LogSource::next_tick_time() const {
  const auto& recs = reader_.records();
  if (next_tick_ >= recs.size()) {
    return -1;
  }
  lf::ByteReader p = reader_.payload(recs[next_tick_]);
  return p.i64();
}

bool LogSource::advance_tick() {
  const auto& recs = reader_.records();
  if (next_tick_ >= recs.size()) {
    return false;
  }
  next_ = next_tick_ + 1;
  next_tick_ = next_;
  while (next_tick_ < recs.size() && recs[next_tick_].type != lf::RecordType::kClock) {
    ++next_tick_;
  }
  in_tick_ = true;
  return true;
}

bool LogSource::read(hal::SensorEvent& out) {
  const auto& recs = reader_.records();
  while (true) {
    if (pacing_ == Pacing::kRecordedTicks) {
      while (next_ < next_tick_ && !lf::is_input(recs[next_].type)) {
        ++next_;
      }
      if (!in_tick_ || next_ >= next_tick_) {
        return false;
      }
    } else {
      skip_to_input();
      if (next_ >= recs.size()) {
        return false;
      }
    }
    const LogRecordRef& r = recs[next_++];
    lf::ByteReader p = reader_.payload(r);
    out = hal::SensorEvent{};
    bool ok = false;
    switch (r.type) {
      case lf::RecordType::kGyro:
        out.kind = hal::SensorEvent::Kind::kGyro;
        ok = lf::decode(p, out.gyro);
        break;
      case lf::RecordType::kEncoder:
        out.kind = hal::SensorEvent::Kind::kEncoder;
        ok = lf::decode(p, out.encoder);
        break;
      case lf::RecordType::kFrame:
        out.kind = hal::SensorEvent::Kind::kFrame;
        ok = lf::decode(p, out.frame, features_.data(), static_cast<int>(features_.size()));
        break;
      case lf::RecordType::kLift:
        out.kind = hal::SensorEvent::Kind::kLift;
        (void)p.i64();
        out.lifted = p.u8() != 0;
        ok = p.ok();
        break;
      default:
        break;
    }
    if (ok) {
      if (pacing_ == Pacing::kEventTime) {
        skip_to_input();
      }
      return true;
    }
    ++payload_defects_;
  }
}

bool LogSource::exhausted() const {
  const auto& recs = reader_.records();
  if (pacing_ == Pacing::kEventTime) {
    std::size_t i = next_;
    while (i < recs.size() && !lf::is_input(recs[i].type)) {
      ++i;
    }
    return i >= recs.size();
  }
  return next_tick_ >= recs.size() && !tick_has_input();
}

}  // namespace cleanslam::readers
