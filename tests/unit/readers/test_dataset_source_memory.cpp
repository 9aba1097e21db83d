#include <gtest/gtest.h>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/dataset_source.hpp"

#if defined(__SANITIZE_ADDRESS__)
// The sanitizer runtime's count of the bytes its allocator holds (declared here: gcc ships the
// runtime but not always its header).
extern "C" std::size_t __sanitizer_get_current_allocated_bytes();
#endif

// The dataset source streams its files: the heap it holds, and the most it uses while the events
// are read, do not grow with the dataset's length.
namespace fs = std::filesystem;
using namespace cleanslam;

namespace {

std::size_t heap_in_use() {
#if defined(__SANITIZE_ADDRESS__)
  return __sanitizer_get_current_allocated_bytes();
#else
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
#endif
}

// A dataset of `seconds`: gyro at 100 Hz, encoders at 20 Hz, a frame every 0.5 s alternately
// with an image (all rows name the same small PGM) and with 8 features, a lift and a set-down.
void write_dataset(const fs::path& dir, std::int64_t seconds) {
  fs::remove_all(dir);
  fs::create_directories(dir / "cam0" / "data");
  hal::Calibration cal;
  cal.camera.width = 32;
  cal.camera.height = 24;
  cal.camera.fx = cal.camera.fy = 28.0;  // the default field of view on this small image
  cal.camera.cx = 15.5;
  cal.camera.cy = 11.5;
  std::ofstream(dir / "sensors.yaml") << readers::sensors_yaml_text(cal);
  {
    std::ofstream pgm(dir / "cam0" / "data" / "f.pgm", std::ios::binary);
    pgm << "P5\n32 24\n255\n" << std::string(std::size_t{32} * 24, '\x40');
  }
  constexpr std::int64_t kMs = 1'000'000;
  std::ofstream gyro(dir / "gyro.csv");
  gyro << "#t_ns,wz_rad_s\n";
  for (std::int64_t i = 0; i < seconds * 100; ++i) {
    gyro << i * 10 * kMs << ",0.01\n";
  }
  std::ofstream enc(dir / "encoders.csv");
  enc << "#t_ns,left_ticks,right_ticks\n";
  for (std::int64_t i = 0; i < seconds * 20; ++i) {
    enc << i * 50 * kMs << "," << i << "," << i << "\n";
  }
  std::ofstream cam(dir / "cam0" / "data.csv");
  cam << "#t_ns,filename\n";
  std::ofstream features(dir / "features.csv");
  features << "#t_ns,track_id,u_px,v_px\n";
  for (std::int64_t i = 0; i < seconds * 2; ++i) {
    const std::int64_t t = i * 500 * kMs + 3;
    if (i % 2 == 0) {
      cam << t << ",f.pgm\n";
    } else {
      for (int k = 0; k < 8; ++k) {
        features << t << "," << (i + k) << ",10.5,12.25\n";
      }
    }
  }
  std::ofstream(dir / "lift.csv") << "#t_ns,lifted\n" << 20 * kMs << ",1\n" << 40 * kMs << ",0\n";
}

struct Use {
  std::size_t events = 0;
  std::size_t held_after_open = 0;  // bytes
  std::size_t peak_while_read = 0;
};

Use stream(const fs::path& dir) {
  Use use;
  const std::size_t before = heap_in_use();
  auto src = readers::DatasetSource::open(dir.string());
  EXPECT_TRUE(src.ok()) << src.error();
  if (!src.ok()) {
    return use;
  }
  use.held_after_open = heap_in_use() - before;
  hal::SensorEvent ev;
  while (src->read(ev)) {
    ++use.events;
    use.peak_while_read = std::max(use.peak_while_read, heap_in_use() - before);
  }
  EXPECT_TRUE(src->exhausted());
  return use;
}

}  // namespace

TEST(DatasetSourceMemory, DoesNotGrowWithTheDatasetsLength) {
  const fs::path root =
      fs::temp_directory_path() / ("cleanslam_stream_" + std::to_string(getpid()));
  write_dataset(root / "short", 60);
  write_dataset(root / "long", 2400);
  const Use short_run = stream(root / "short");
  const Use long_run = stream(root / "long");
  fs::remove_all(root);
  RecordProperty("short_held_bytes", std::to_string(short_run.held_after_open));
  RecordProperty("long_held_bytes", std::to_string(long_run.held_after_open));
  RecordProperty("short_peak_bytes", std::to_string(short_run.peak_while_read));
  RecordProperty("long_peak_bytes", std::to_string(long_run.peak_while_read));
  ASSERT_EQ(short_run.events, std::size_t{60} * (100 + 20 + 2) + 2);
  ASSERT_EQ(long_run.events, std::size_t{2400} * (100 + 20 + 2) + 2);
  // A source that kept its rows would hold 40 times the short one's (megabytes here).
  constexpr std::size_t kSlack = std::size_t{16} * 1024;
  EXPECT_LE(long_run.held_after_open, short_run.held_after_open + kSlack)
      << "short " << short_run.held_after_open << " bytes, long " << long_run.held_after_open;
  EXPECT_LE(long_run.peak_while_read, short_run.peak_while_read + kSlack)
      << "short " << short_run.peak_while_read << " bytes, long " << long_run.peak_while_read;
  EXPECT_LT(short_run.held_after_open, std::size_t{256} * 1024) << short_run.held_after_open;
}
