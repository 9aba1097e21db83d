#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/interfaces.hpp"
#include "cleanslam/hal/log_format.hpp"

namespace cleanslam::readers {

// Why a stretch of a log was skipped.
enum class LogDefect : std::uint8_t {
  kBadSync,     // bytes that do not start a record (skipped up to the next sync word)
  kBadLength,   // a length beyond the format's maximum
  kBadCrc,      // checksum mismatch
  kTruncated,   // the file ends inside a record (power loss): replay stops before it
  kBadPayload,  // checksum fine but the payload does not decode
  kCount
};
const char* to_string(LogDefect d);

struct LogRecordRef {
  std::size_t offset = 0;  // of the record header in the file
  hal::log::RecordType type = hal::log::RecordType::kClock;
  std::uint32_t length = 0;
};

// A whole log file in memory, indexed: the valid records in file order and the defects met.
class LogReader {
 public:
  // Reads and indexes `path`; false with `error()` set when the file is unreadable or is not a
  // log. A damaged or truncated file still opens: its defects are counted.
  bool open(const std::string& path);
  bool open_bytes(std::vector<std::uint8_t> bytes, const std::string& name = "<memory>");

  [[nodiscard]] const std::string& error() const { return error_; }
  [[nodiscard]] const std::vector<LogRecordRef>& records() const { return records_; }
  [[nodiscard]] std::uint64_t defects(LogDefect d) const {
    return defects_[static_cast<std::size_t>(d)];
  }
  [[nodiscard]] std::uint64_t total_defects() const;
  // Offset of the first byte not covered by a whole record when the file is truncated.
  [[nodiscard]] std::size_t truncated_at() const { return truncated_at_; }
  [[nodiscard]] std::size_t file_size() const { return bytes_.size(); }
  [[nodiscard]] const std::string& name() const { return name_; }

  [[nodiscard]] hal::log::ByteReader payload(const LogRecordRef& r) const {
    return {bytes_.data() + r.offset + hal::log::kRecordHeaderSize, r.length};
  }
  // The first configuration record: its text and hash. Empty when there is none.
  [[nodiscard]] std::string_view config_text() const { return config_text_; }
  [[nodiscard]] std::uint64_t config_hash() const { return config_hash_; }
  [[nodiscard]] bool has_config() const { return has_config_; }
  // Raw bytes of a record (header included), for bit-exact comparison.
  [[nodiscard]] const std::uint8_t* record_bytes(const LogRecordRef& r) const {
    return bytes_.data() + r.offset;
  }

 private:
  void index();
  std::vector<std::uint8_t> bytes_;
  std::vector<LogRecordRef> records_;
  std::array<std::uint64_t, static_cast<std::size_t>(LogDefect::kCount)> defects_{};
  std::size_t truncated_at_ = 0;
  std::string error_;
  std::string name_;
  std::string_view config_text_;
  std::uint64_t config_hash_ = 0;
  bool has_config_ = false;
};

// The recorded inputs of a log as a hal::SensorSource, on a virtual clock (fd() is -1).
//  - kEventTime: events are due at their own time stamps (a log used like a dataset).
//  - kRecordedTicks: events are released one loop iteration at a time, as the recording loop
//    ingested them; the iteration times come from the log's clock records (bit-exact replay).
//    Released events are ready at once (next_event_time() is -1, as for a live device).
class LogSource final : public hal::SensorSource {
 public:
  enum class Pacing : std::uint8_t { kEventTime, kRecordedTicks };

  LogSource(const LogReader& reader, Pacing pacing);

  [[nodiscard]] hal::TimeNs next_event_time() const override;
  bool read(hal::SensorEvent& out) override;
  [[nodiscard]] bool exhausted() const override;

  // kRecordedTicks: time of the next recorded loop iteration, or -1 at the end. Advancing
  // releases the events that iteration ingested.
  [[nodiscard]] hal::TimeNs next_tick_time() const;
  bool advance_tick();

  [[nodiscard]] std::uint64_t payload_defects() const { return payload_defects_; }

 private:
  void skip_to_input();
  [[nodiscard]] bool tick_has_input() const;
  [[nodiscard]] hal::TimeNs event_time(const LogRecordRef& r) const;

  const LogReader& reader_;
  Pacing pacing_;
  std::size_t next_ = 0;       // next record index to examine
  std::size_t next_tick_ = 0;  // index of the next clock record (kRecordedTicks)
  bool in_tick_ = false;
  std::uint64_t payload_defects_ = 0;
  std::array<hal::FeatureObservation, hal::kMaxFeaturesPerFrame> features_{};
};

}  // namespace cleanslam::readers
