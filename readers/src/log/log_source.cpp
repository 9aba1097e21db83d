#include "cleanslam/readers/log_source.hpp"

#include <algorithm>
#include <cstdio>

namespace cleanslam::readers {

namespace lf = hal::log;

LogSource::LogSource(const LogReader& reader, Pacing pacing, hal::TimeNs max_span_ns)
    : reader_(reader), pacing_(pacing) {
  // The log's start: the earlier of its first clock record and its first input.
  bool clock_seen = false;
  bool input_seen = false;
  for (const LogRecordRef& r : reader_.records()) {
    const bool clock = r.type == lf::RecordType::kClock;
    if ((clock && !clock_seen) || (lf::is_input(r.type) && !input_seen)) {
      const hal::TimeNs t = event_time(r);
      if (t >= 0 && (start_ns_ < 0 || t < start_ns_)) {
        start_ns_ = t;
      }
      (clock ? clock_seen : input_seen) = true;
    }
    if (clock_seen && input_seen) {
      break;
    }
  }
  end_ns_ = hal::add_saturated(std::max<hal::TimeNs>(start_ns_, 0), max_span_ns);
  span_s_ = hal::to_seconds(max_span_ns);
  if (pacing_ == Pacing::kEventTime) {
    skip_to_input();
  } else {
    skip_to_clock();
    next_ = next_tick_;
  }
}

void LogSource::tell(const LogRecordRef& r, const std::string& what) {
  if (messages_.size() < kMaxMessages) {
    messages_.push_back(reader_.name() + ": offset " + std::to_string(r.offset) + ": " +
                        lf::to_string(r.type) + " record: " + what);
  }
}

bool LogSource::plausible(const LogRecordRef& r) {
  const hal::TimeNs t = event_time(r);
  if (t >= 0 && t <= end_ns_) {
    return true;
  }
  ++stamps_refused_;
  char span[32];
  std::snprintf(span, sizeof span, "%g", span_s_);
  tell(r, "time stamp " + std::to_string(t) +
              (t < 0 ? " is negative"
                     : " is more than " + std::string(span) +
                           " s (loop.max_span_s) after the log's first, " +
                           std::to_string(start_ns_)) +
              ": refused");
  return false;
}

bool LogSource::in_place(std::size_t i) {
  constexpr std::size_t kLookahead = 256;
  const auto& recs = reader_.records();
  const LogRecordRef& r = recs[i];
  const hal::TimeNs t = event_time(r);
  hal::TimeNs& previous =
      last_delivered_[static_cast<std::size_t>(r.type) % last_delivered_.size()];
  for (std::size_t j = i + 1; j < recs.size() && j <= i + kLookahead; ++j) {
    if (recs[j].type != r.type) {
      continue;
    }
    const hal::TimeNs next = event_time(recs[j]);
    // Stamped after the next sample of its sensor, which follows the previous one: this sample
    // is the one out of place (were it kept, the clock would run ahead to it and the samples in
    // between would arrive late and be dropped). Else the next one is, and the loop drops it.
    if (next < t && (previous < 0 || next > previous)) {
      ++out_of_place_;
      tell(r, "time stamp " + std::to_string(t) + " is after that of the next " +
                  lf::to_string(r.type) + " record (offset " + std::to_string(recs[j].offset) +
                  ", " + std::to_string(next) + "): out of place, refused");
      return false;
    }
    break;
  }
  previous = t;
  return true;
}

void LogSource::skip_to_input() {
  const auto& recs = reader_.records();
  while (next_ < recs.size() &&
         (!lf::is_input(recs[next_].type) || !plausible(recs[next_]) || !in_place(next_))) {
    ++next_;
  }
}

void LogSource::skip_to_clock() {
  const auto& recs = reader_.records();
  while (next_tick_ < recs.size() &&
         (recs[next_tick_].type != lf::RecordType::kClock || !plausible(recs[next_tick_]))) {
    ++next_tick_;
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
  skip_to_clock();
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
    tell(r, std::to_string(r.length) +
                " payload bytes with a valid checksum that do not decode: "
                "skipped");
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
