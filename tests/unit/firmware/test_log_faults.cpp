#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cleanslam/firmware/recorder.hpp"
#include "cleanslam/hal/log_format.hpp"
#include "cleanslam/readers/log_source.hpp"
#include "text_checks.hpp"
#include "time_units.hpp"

// Faults of a log that get through the checksum: each is refused or told with the record's type
// and offset, and costs no more than its own record.
namespace cleanslam {
namespace {

namespace fs = std::filesystem;
namespace lf = hal::log;
using readers::LogReader;
using readers::LogSource;

using test::kMs;
using test::kS;

// A log built record by record: every record sealed with a valid checksum.
class LogBuilder {
 public:
  LogBuilder() {
    bytes_.resize(lf::kFileHeaderSize);
    lf::ByteWriter w(bytes_.data(), bytes_.size());
    lf::write_file_header(w);
  }
  template <typename Encode>
  std::size_t add(lf::RecordType type, std::size_t size, const Encode& encode) {
    const std::size_t at = bytes_.size();
    bytes_.resize(at + lf::kRecordHeaderSize + size);
    lf::ByteWriter w(bytes_.data() + at + lf::kRecordHeaderSize, size);
    encode(w);
    lf::seal_record(bytes_.data() + at, type, static_cast<std::uint32_t>(size));
    return at;
  }
  std::size_t config(const std::string& text, std::uint64_t hash) {
    return add(lf::RecordType::kConfig, 8 + text.size(), [&](lf::ByteWriter& w) {
      w.u64(hash);
      w.bytes(text.data(), text.size());
    });
  }
  std::size_t gyro(hal::TimeNs t) {
    return add(lf::RecordType::kGyro, lf::kGyroPayload, [&](lf::ByteWriter& w) {
      lf::encode(w, hal::GyroSample{t, 0.1, 0, 0, false, 0});
    });
  }
  std::size_t encoder(hal::TimeNs t) {
    return add(lf::RecordType::kEncoder, lf::kEncoderPayload, [&](lf::ByteWriter& w) {
      lf::encode(w, hal::EncoderSample{t, 1, 2, 0});
    });
  }
  // Gyro at 100 Hz and encoders at 20 Hz over [t0, t1); `stamp` may alter the stamp of each.
  template <typename Stamp>
  void drive(hal::TimeNs t0, hal::TimeNs t1, const Stamp& stamp) {
    int k = 0;
    for (hal::TimeNs t = t0; t < t1; t += 10 * kMs, ++k) {
      gyro(stamp(lf::RecordType::kGyro, k, t));
      if (k % 5 == 0) {
        encoder(stamp(lf::RecordType::kEncoder, k / 5, t));
      }
    }
  }
  [[nodiscard]] std::vector<std::uint8_t> bytes() const { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

auto unaltered() {
  return [](lf::RecordType, int, hal::TimeNs t) { return t; };
}

struct Read {
  int gyro = 0;
  int encoders = 0;
  hal::TimeNs max_stamp = -1;
};

Read read_all_events(LogSource& src) {
  Read r;
  hal::SensorEvent ev;
  while (src.read(ev)) {
    if (ev.kind == hal::SensorEvent::Kind::kGyro) {
      ++r.gyro;
      r.max_stamp = std::max(r.max_stamp, ev.gyro.t_ns);
    } else if (ev.kind == hal::SensorEvent::Kind::kEncoder) {
      ++r.encoders;
      r.max_stamp = std::max(r.max_stamp, ev.encoder.t_ns);
    }
  }
  return r;
}

using test::contains;

TEST(LogFaults, StampsPastTheSpanOrNegativeAreRefusedWithTheirOffset) {
  for (const hal::TimeNs bad :
       {hal::kTimeMax, hal::TimeNs{9'000'000'000'000'000'000},
        hal::TimeNs{2 * kS + hal::TimeNs{365} * 86'400 * kS}, hal::kTimeMin}) {
    LogBuilder b;
    b.drive(1 * kS, 2 * kS, unaltered());
    const std::size_t at = b.gyro(bad);
    b.drive(2 * kS, 3 * kS, unaltered());
    LogReader reader;
    ASSERT_TRUE(reader.open_bytes(b.bytes(), "bad.log"));
    LogSource src(reader, LogSource::Pacing::kEventTime);
    const Read r = read_all_events(src);
    EXPECT_EQ(r.gyro, 200) << bad;
    EXPECT_EQ(r.encoders, 40) << bad;
    EXPECT_EQ(r.max_stamp, 2990 * kMs) << bad;
    EXPECT_EQ(src.stamps_refused(), 1U) << bad;
    ASSERT_EQ(src.messages().size(), 1U) << bad;
    const std::string& m = src.messages()[0];
    EXPECT_TRUE(contains(m, "bad.log: offset " + std::to_string(at) + ": gyro record: time stamp " +
                                std::to_string(bad)))
        << m;
    EXPECT_TRUE(contains(m, bad < 0 ? "is negative: refused" : "(loop.max_span_s)")) << m;
  }
}

TEST(LogFaults, AClockRecordPastTheSpanIsSkippedAndTold) {
  LogBuilder b;
  for (hal::TimeNs t = 1 * kS; t < 2 * kS; t += 10 * kMs) {
    const hal::TimeNs clock = t == 1500 * kMs ? hal::kTimeMax : t;
    b.add(lf::RecordType::kClock, 8, [&](lf::ByteWriter& w) { w.i64(clock); });
    b.gyro(t);
  }
  LogReader reader;
  ASSERT_TRUE(reader.open_bytes(b.bytes(), "clock.log"));
  LogSource src(reader, LogSource::Pacing::kRecordedTicks);
  int ticks = 0;
  hal::TimeNs last = 0;
  while (src.next_tick_time() >= 0) {
    last = src.next_tick_time();
    ASSERT_LT(last, 2 * kS);
    src.advance_tick();
    ++ticks;
  }
  EXPECT_EQ(ticks, 99);
  EXPECT_EQ(src.stamps_refused(), 1U);
  ASSERT_EQ(src.messages().size(), 1U);
  EXPECT_TRUE(contains(src.messages()[0], "clock record: time stamp 9223372036854775807"))
      << src.messages()[0];
}

TEST(LogFaults, ASampleStampedAheadOfTheNextCostsOnlyItself) {
  // Encoder 10 stamped 0.9 s ahead: as the log's order it would hold the clock and make the
  // next 18 encoder samples late.
  LogBuilder b;
  b.drive(1 * kS, 3 * kS, [](lf::RecordType type, int k, hal::TimeNs t) {
    return type == lf::RecordType::kEncoder && k == 10 ? t + 900 * kMs : t;
  });
  LogReader reader;
  ASSERT_TRUE(reader.open_bytes(b.bytes(), "early.log"));
  LogSource src(reader, LogSource::Pacing::kEventTime);
  hal::SensorEvent ev;
  hal::TimeNs last = -1;
  int encoders = 0;
  while (src.read(ev)) {
    if (ev.kind == hal::SensorEvent::Kind::kEncoder) {
      EXPECT_GT(ev.encoder.t_ns, last);
      last = ev.encoder.t_ns;
      ++encoders;
    }
  }
  EXPECT_EQ(encoders, 39);
  EXPECT_EQ(src.out_of_place(), 1U);
  ASSERT_EQ(src.messages().size(), 1U);
  EXPECT_TRUE(contains(src.messages()[0],
                       "encoder record: time stamp 2400000000 is after that "
                       "of the next encoder record"))
      << src.messages()[0];
}

TEST(LogFaults, ASampleStampedBehindLeavesTheOneBeforeIt) {
  // Encoder 10 stamped 0.3 s behind: it is the one out of place (the loop drops it as out of
  // order); encoder 9, stamped after it, is kept.
  LogBuilder b;
  b.drive(1 * kS, 3 * kS, [](lf::RecordType type, int k, hal::TimeNs t) {
    return type == lf::RecordType::kEncoder && k == 10 ? t - 300 * kMs : t;
  });
  LogReader reader;
  ASSERT_TRUE(reader.open_bytes(b.bytes(), "late.log"));
  LogSource src(reader, LogSource::Pacing::kEventTime);
  EXPECT_EQ(read_all_events(src).encoders, 40);
  EXPECT_EQ(src.out_of_place(), 0U);
}

TEST(LogFaults, APayloadThatDoesNotDecodeIsNamedByTypeAndOffset) {
  LogBuilder b;
  b.drive(1 * kS, 2 * kS, unaltered());
  const std::size_t at = b.add(lf::RecordType::kGyro, 10, [](lf::ByteWriter& w) {
    w.i64(2 * kS);
    w.u16(0);
  });
  b.drive(2 * kS, 3 * kS, unaltered());
  LogReader reader;
  ASSERT_TRUE(reader.open_bytes(b.bytes(), "short.log"));
  LogSource src(reader, LogSource::Pacing::kEventTime);
  EXPECT_EQ(read_all_events(src).gyro, 200);
  EXPECT_EQ(src.payload_defects(), 1U);
  ASSERT_EQ(src.messages().size(), 1U);
  EXPECT_EQ(src.messages()[0], "short.log: offset " + std::to_string(at) +
                                   ": gyro record: 10 payload bytes with a valid checksum that "
                                   "do not decode: skipped");
}

TEST(LogFaults, AConfigurationWhoseHashIsNotItsTextsIsFound) {
  const std::string text = "loop:\n  publish_rate_hz: 20\n";
  for (const bool altered : {false, true}) {
    LogBuilder b;
    b.config(altered ? "loop:\n  publish_rate_hz: 10\n" : text,
             lf::fnv1a64(text.data(), text.size()));
    b.drive(1 * kS, 2 * kS, unaltered());
    LogReader reader;
    ASSERT_TRUE(reader.open_bytes(b.bytes()));
    ASSERT_TRUE(reader.has_config());
    EXPECT_EQ(reader.config_hash_matches(), !altered);
  }
}

TEST(LogFaults, RotatedFilesKnowTheirIndexAndJoinInOrderOnly) {
  const fs::path dir =
      fs::temp_directory_path() / ("cleanslam_test_join_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  firmware::Recorder rec;
  firmware::RecorderOptions opt;
  opt.path = (dir / "run.log").string();
  opt.max_file_bytes = 4096;
  opt.max_files = 3;
  std::string error;
  ASSERT_TRUE(rec.open(opt, "x: 1\n", error));
  for (hal::TimeNs t = 1 * kS; t < 5 * kS; t += 10 * kMs) {
    rec.clock(t);
    rec.gyro(hal::GyroSample{t, 0.1, 0, 0, false, 0});
  }
  rec.close();
  ASSERT_GE(rec.stats().rotations, 3U);
  const auto file = [&](const char* name) {
    std::ifstream in(dir / name, std::ios::binary);
    return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
  };
  const auto n = static_cast<std::uint32_t>(rec.stats().rotations);
  LogReader newest;
  ASSERT_TRUE(newest.open_bytes(file("run.log")));
  EXPECT_EQ(newest.file_index(), n);
  const auto join = [&](std::initializer_list<const char*> names) {
    std::vector<std::uint8_t> bytes;
    for (const char* name : names) {
      const auto f = file(name);
      bytes.insert(bytes.end(), f.begin(), f.end());
    }
    return bytes;
  };
  LogReader joined;
  ASSERT_TRUE(joined.open_bytes(join({"run.log.2", "run.log.1", "run.log"})));
  EXPECT_EQ(joined.file_index(), n - 2);
  EXPECT_EQ(joined.files_joined(), 3);
  EXPECT_EQ(joined.join_error(), "");
  EXPECT_EQ(joined.total_defects(), 0U);
  LogReader gap;
  ASSERT_TRUE(gap.open_bytes(join({"run.log.2", "run.log"})));
  EXPECT_TRUE(contains(gap.join_error(), "a file with index " + std::to_string(n) +
                                             " (format version 1) follows the file with index " +
                                             std::to_string(n - 2) +
                                             ": a file of the recording "
                                             "is missing or out of order"))
      << gap.join_error();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cleanslam
