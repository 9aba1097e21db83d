#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cleanslam/firmware/recorder.hpp"
#include "cleanslam/hal/log_format.hpp"
#include "cleanslam/readers/log_source.hpp"

namespace cleanslam {
namespace {

namespace fs = std::filesystem;
namespace lf = hal::log;
using firmware::Recorder;
using firmware::RecorderOptions;
using readers::LogDefect;
using readers::LogReader;
using readers::LogSource;

fs::path temp_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("cleanslam_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::vector<std::uint8_t> read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(LogFormat, Crc32MatchesTheStandardCheckValue) {
  const std::string s = "123456789";
  EXPECT_EQ(lf::crc32_update(0, reinterpret_cast<const std::uint8_t*>(s.data()), s.size()),
            0xCBF43926U);
  // Running CRC over two pieces equals the CRC of the whole.
  const auto* p = reinterpret_cast<const std::uint8_t*>(s.data());
  EXPECT_EQ(lf::crc32_update(lf::crc32_update(0, p, 4), p + 4, 5), 0xCBF43926U);
}

TEST(LogFormat, PayloadSizesMatchTheEncoders) {
  std::vector<std::uint8_t> buf(1024);
  const auto size_of = [&](auto&& enc) {
    lf::ByteWriter w(buf.data(), buf.size());
    enc(w);
    EXPECT_TRUE(w.ok());
    return w.size();
  };
  EXPECT_EQ(size_of([](lf::ByteWriter& w) { lf::encode(w, hal::GyroSample{}); }), lf::kGyroPayload);
  EXPECT_EQ(size_of([](lf::ByteWriter& w) { lf::encode(w, hal::EncoderSample{}); }),
            lf::kEncoderPayload);
  EXPECT_EQ(size_of([](lf::ByteWriter& w) { lf::encode(w, hal::PoseEstimate{}); }),
            lf::kPosePayload);
  EXPECT_EQ(size_of([](lf::ByteWriter& w) { lf::encode(w, lf::UpdateRecord{}); }),
            lf::kUpdatePayload);
  EXPECT_EQ(size_of([](lf::ByteWriter& w) { lf::encode_lift(w, 5, true); }), lf::kLiftPayload);
}

TEST(LogFormat, WriterRefusesToOverflow) {
  std::uint8_t buf[4];
  lf::ByteWriter w(buf, sizeof buf);
  w.u64(1);
  EXPECT_FALSE(w.ok());
  lf::ByteReader r(buf, 2);
  (void)r.u32();
  EXPECT_FALSE(r.ok());
}

struct Recorded {
  std::vector<hal::GyroSample> gyro;
  std::vector<hal::EncoderSample> enc;
  std::vector<std::uint8_t> image;
  std::vector<hal::FeatureObservation> features;
};

// A small run: clock ticks, gyro, encoder, one frame with image and features, poses.
void record_run(Recorder& rec, Recorded& r, int ticks) {
  r.image.resize(32 * 24);
  for (std::size_t i = 0; i < r.image.size(); ++i) {
    r.image[i] = static_cast<std::uint8_t>(i * 7);
  }
  r.features = {{3, 10.25, 20.5}, {9, -1.0, 1e-9}};
  for (int k = 0; k < ticks; ++k) {
    const hal::TimeNs t = 1'000'000'000 + hal::TimeNs{k} * 10'000'000;
    rec.clock(t);
    hal::GyroSample g{t, 0.01 * k, 0.0, 0.0, false, static_cast<std::uint32_t>(k)};
    rec.gyro(g);
    r.gyro.push_back(g);
    if (k % 5 == 0) {
      hal::EncoderSample e{t, 100 * k, -100 * k, static_cast<std::uint32_t>(k / 5)};
      rec.encoder(e);
      r.enc.push_back(e);
    }
    if (k == 3) {
      hal::CameraFrame f;
      f.t_ns = t;
      f.seq = 7;
      f.image = hal::GrayImageView{r.image.data(), 32, 24, 32};
      f.features = r.features.data();
      f.feature_count = 2;
      rec.frame(f);
    }
    hal::PoseEstimate p;
    p.t_ns = t;
    p.position_m = {0.1 * k, 0.0, 0.0};
    p.health = static_cast<std::uint32_t>(k);
    rec.pose(p);
  }
}

TEST(Recorder, RecordsReadBackThroughTheLogSource) {
  const fs::path dir = temp_dir("rec");
  Recorder rec;
  std::string error;
  RecorderOptions opt;
  opt.path = (dir / "run.log").string();
  ASSERT_TRUE(rec.open(opt, "filter: {}\n", error)) << error;
  Recorded r;
  record_run(rec, r, 20);
  rec.close();

  LogReader reader;
  ASSERT_TRUE(reader.open(opt.path)) << reader.error();
  EXPECT_EQ(reader.total_defects(), 0U);
  ASSERT_TRUE(reader.has_config());
  EXPECT_EQ(reader.config_text(), "filter: {}\n");
  EXPECT_EQ(reader.config_hash(), lf::fnv1a64("filter: {}\n", 11));

  LogSource src(reader, LogSource::Pacing::kEventTime);
  std::size_t gyro = 0;
  std::size_t enc = 0;
  int frames = 0;
  hal::SensorEvent ev;
  hal::TimeNs last = 0;
  while (src.next_event_time() >= 0) {
    const hal::TimeNs t = src.next_event_time();
    ASSERT_GE(t, last);
    last = t;
    ASSERT_TRUE(src.read(ev));
    switch (ev.kind) {
      case hal::SensorEvent::Kind::kGyro:
        ASSERT_LT(gyro, r.gyro.size());
        EXPECT_EQ(ev.gyro.t_ns, r.gyro[gyro].t_ns);
        EXPECT_EQ(ev.gyro.wz_rad_s, r.gyro[gyro].wz_rad_s);
        EXPECT_EQ(ev.gyro.seq, r.gyro[gyro].seq);
        ++gyro;
        break;
      case hal::SensorEvent::Kind::kEncoder:
        EXPECT_EQ(ev.encoder.left_ticks, r.enc[enc].left_ticks);
        EXPECT_EQ(ev.encoder.right_ticks, r.enc[enc].right_ticks);
        ++enc;
        break;
      case hal::SensorEvent::Kind::kFrame: {
        ++frames;
        EXPECT_EQ(ev.frame.seq, 7U);
        ASSERT_TRUE(ev.frame.has_image());
        EXPECT_EQ(ev.frame.image.width, 32);
        EXPECT_EQ(ev.frame.image.at(5, 2), r.image[2 * 32 + 5]);
        ASSERT_EQ(ev.frame.feature_count, 2);
        EXPECT_EQ(ev.frame.features[0].track_id, 3);
        EXPECT_EQ(ev.frame.features[1].v_px, 1e-9);
        break;
      }
      default:
        ADD_FAILURE() << "unexpected event";
    }
  }
  EXPECT_TRUE(src.exhausted());
  EXPECT_FALSE(src.read(ev));
  EXPECT_EQ(gyro, r.gyro.size());
  EXPECT_EQ(enc, r.enc.size());
  EXPECT_EQ(frames, 1);
  fs::remove_all(dir);
}

TEST(Recorder, RecordedTicksReleaseEventsOneIterationAtATime) {
  const fs::path dir = temp_dir("ticks");
  Recorder rec;
  std::string error;
  RecorderOptions opt;
  opt.path = (dir / "run.log").string();
  ASSERT_TRUE(rec.open(opt, "x: 1\n", error)) << error;
  Recorded r;
  record_run(rec, r, 6);
  rec.close();
  LogReader reader;
  ASSERT_TRUE(reader.open(opt.path));
  LogSource src(reader, LogSource::Pacing::kRecordedTicks);
  hal::SensorEvent ev;
  EXPECT_FALSE(src.read(ev));  // nothing before the first iteration
  for (int k = 0; k < 6; ++k) {
    ASSERT_EQ(src.next_tick_time(), 1'000'000'000 + hal::TimeNs{k} * 10'000'000);
    ASSERT_TRUE(src.advance_tick());
    int events = 0;
    while (src.read(ev)) {
      ++events;
    }
    EXPECT_EQ(events, 1 + (k % 5 == 0 ? 1 : 0) + (k == 3 ? 1 : 0)) << "iteration " << k;
  }
  EXPECT_EQ(src.next_tick_time(), -1);
  EXPECT_FALSE(src.advance_tick());
  EXPECT_TRUE(src.exhausted());
  fs::remove_all(dir);
}

// A log cut at any byte opens, keeps every whole record before the cut, and reports the
// truncation unless the cut falls on a record boundary.
TEST(LogReader, TruncatedAtEveryByteReplaysUpToTheLastWholeRecord) {
  const fs::path dir = temp_dir("trunc");
  Recorder rec;
  std::string error;
  RecorderOptions opt;
  opt.path = (dir / "run.log").string();
  ASSERT_TRUE(rec.open(opt, "k: v\n", error));
  Recorded r;
  record_run(rec, r, 8);
  rec.close();
  const std::vector<std::uint8_t> whole = read_all(opt.path);
  LogReader full;
  ASSERT_TRUE(full.open_bytes(whole));
  const auto& recs = full.records();
  ASSERT_GT(recs.size(), 20U);
  for (std::size_t cut = lf::kFileHeaderSize; cut < whole.size(); ++cut) {
    LogReader part;
    ASSERT_TRUE(part.open_bytes({whole.begin(), whole.begin() + static_cast<long>(cut)}));
    std::size_t whole_records = 0;
    bool boundary = cut == lf::kFileHeaderSize;
    for (const auto& rr : recs) {
      const std::size_t end = rr.offset + lf::kRecordHeaderSize + rr.length;
      if (end <= cut) {
        ++whole_records;
      }
      boundary = boundary || end == cut;
    }
    ASSERT_EQ(part.records().size(), whole_records) << "cut at " << cut;
    EXPECT_EQ(part.defects(LogDefect::kTruncated), boundary ? 0U : 1U) << "cut at " << cut;
    EXPECT_EQ(part.total_defects(), boundary ? 0U : 1U) << "cut at " << cut;
  }
  fs::remove_all(dir);
}

TEST(LogReader, CorruptRecordsAreCountedAndSkipped) {
  const fs::path dir = temp_dir("corrupt");
  Recorder rec;
  std::string error;
  RecorderOptions opt;
  opt.path = (dir / "run.log").string();
  ASSERT_TRUE(rec.open(opt, "k: v\n", error));
  Recorded r;
  record_run(rec, r, 8);
  rec.close();
  std::vector<std::uint8_t> bytes = read_all(opt.path);
  LogReader full;
  ASSERT_TRUE(full.open_bytes(bytes));
  const auto recs = full.records();
  // Flip a payload bit of record 5, the sync word of record 9, and the length of record 12 to
  // something huge.
  bytes[recs[5].offset + lf::kRecordHeaderSize] ^= 0x10;
  bytes[recs[9].offset] ^= 0xFF;
  bytes[recs[12].offset + 7] = 0x7F;
  LogReader damaged;
  ASSERT_TRUE(damaged.open_bytes(bytes));
  EXPECT_EQ(damaged.defects(LogDefect::kBadCrc), 1U);
  EXPECT_EQ(damaged.defects(LogDefect::kBadSync), 1U);
  EXPECT_EQ(damaged.defects(LogDefect::kBadLength), 1U);
  EXPECT_EQ(damaged.defects(LogDefect::kTruncated), 0U);
  EXPECT_EQ(damaged.records().size(), recs.size() - 3);
  // Garbage in front of the first record is skipped as one stretch.
  std::vector<std::uint8_t> prefixed(bytes.begin(), bytes.begin() + lf::kFileHeaderSize);
  prefixed.insert(prefixed.end(), {1, 2, 3, 4, 5});
  prefixed.insert(prefixed.end(), bytes.begin() + lf::kFileHeaderSize, bytes.end());
  LogReader shifted;
  ASSERT_TRUE(shifted.open_bytes(prefixed));
  EXPECT_EQ(shifted.defects(LogDefect::kBadSync), 2U);
  EXPECT_EQ(shifted.records().size(), recs.size() - 3);
  fs::remove_all(dir);
}

TEST(LogReader, RejectsAFileThatIsNotALog) {
  LogReader reader;
  EXPECT_FALSE(reader.open_bytes({'h', 'e', 'l', 'l', 'o'}, "x.log"));
  EXPECT_NE(reader.error().find("x.log"), std::string::npos);
  EXPECT_FALSE(reader.open("/nonexistent/cleanslam.log"));
}

TEST(Recorder, RotatesAtTheSizeLimitAndEachFileStandsAlone) {
  const fs::path dir = temp_dir("rotate");
  Recorder rec;
  std::string error;
  RecorderOptions opt;
  opt.path = (dir / "run.log").string();
  opt.max_file_bytes = 4096;
  opt.max_files = 3;
  ASSERT_TRUE(rec.open(opt, "rotate: true\n", error));
  Recorded r;
  record_run(rec, r, 200);
  rec.close();
  EXPECT_GT(rec.stats().rotations, 3U);
  EXPECT_TRUE(fs::exists(dir / "run.log"));
  EXPECT_TRUE(fs::exists(dir / "run.log.1"));
  EXPECT_TRUE(fs::exists(dir / "run.log.2"));
  EXPECT_FALSE(fs::exists(dir / "run.log.3"));
  for (const char* name : {"run.log", "run.log.1", "run.log.2"}) {
    EXPECT_LE(fs::file_size(dir / name), opt.max_file_bytes) << name;
    LogReader reader;
    ASSERT_TRUE(reader.open((dir / name).string())) << name;
    EXPECT_EQ(reader.total_defects(), 0U) << name;
    EXPECT_EQ(reader.config_text(), "rotate: true\n") << name;
  }
  // The newest file holds the last records of the run.
  LogReader newest;
  ASSERT_TRUE(newest.open((dir / "run.log").string()));
  hal::PoseEstimate last;
  for (const auto& rr : newest.records()) {
    if (rr.type == lf::RecordType::kPose) {
      auto p = newest.payload(rr);
      ASSERT_TRUE(lf::decode(p, last));
    }
  }
  EXPECT_EQ(last.health, 199U);
  fs::remove_all(dir);
}

TEST(Recorder, WritesInBoundedChunksAndCountsWhatDoesNotFit) {
  const fs::path dir = temp_dir("chunks");
  Recorder rec;
  std::string error;
  RecorderOptions opt;
  opt.path = (dir / "run.log").string();
  opt.write_chunk_bytes = 100;
  ASSERT_TRUE(rec.open(opt, "", error));
  for (int i = 0; i < 50; ++i) {
    rec.gyro(hal::GyroSample{i, 0.0, 0.0, 0.0, false, 0});
  }
  const std::size_t before = rec.pending_bytes();
  rec.write_some();
  EXPECT_EQ(before - rec.pending_bytes(), 100U);
  rec.flush(true);
  EXPECT_EQ(rec.pending_bytes(), 0U);
  EXPECT_EQ(rec.stats().dropped_buffer_full, 0U);
  // frame_every = 2 records frames 0, 2, 4.
  RecorderOptions every2 = opt;
  every2.path = (dir / "k.log").string();
  every2.frame_every = 2;
  Recorder rec2;
  ASSERT_TRUE(rec2.open(every2, "", error));
  std::vector<hal::FeatureObservation> feats{{1, 2.0, 3.0}};
  for (std::uint32_t i = 0; i < 5; ++i) {
    hal::CameraFrame f;
    f.t_ns = i;
    f.seq = i;
    f.features = feats.data();
    f.feature_count = 1;
    rec2.frame(f);
  }
  rec2.close();
  EXPECT_EQ(rec2.stats().frames_skipped, 2U);
  LogReader reader;
  ASSERT_TRUE(reader.open(every2.path));
  int frames = 0;
  for (const auto& rr : reader.records()) {
    frames += rr.type == lf::RecordType::kFrame ? 1 : 0;
  }
  EXPECT_EQ(frames, 3);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cleanslam
