#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/output_report.hpp"
#include "cleanslam/firmware/recorder.hpp"
#include "cleanslam/firmware/rotating_file.hpp"
#include "cleanslam/firmware/sinks.hpp"
#include "text_checks.hpp"

namespace cleanslam {
namespace {

namespace fs = std::filesystem;
using firmware::Rotation;

using test::contains;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class Outputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cleanslam_outputs_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

hal::PoseEstimate pose(int i) {
  hal::PoseEstimate p;
  p.t_ns = i * 20'000'000LL;
  p.position_m = {0.01 * i, 0.0, 0.0};
  return p;
}

TEST_F(Outputs, TumAndCovarianceRotateTogetherAndStayBounded) {
  firmware::TumWriter tum;
  std::string error;
  const std::string path = (dir_ / "t.tum").string();
  ASSERT_TRUE(tum.open(path, false, true, error, Rotation{4000, 3})) << error;
  for (int i = 0; i < 200; ++i) {
    tum.publish(pose(i));
  }
  EXPECT_GT(tum.file().rotations(), 3U);
  ASSERT_TRUE(tum.close());
  // The .cov of a rotated file is FILE.cov's own rotation: t.tum.cov.1.
  EXPECT_TRUE(fs::exists(dir_ / "t.tum.1"));
  EXPECT_TRUE(fs::exists(dir_ / "t.tum.2"));
  EXPECT_FALSE(fs::exists(dir_ / "t.tum.3"));
  EXPECT_TRUE(fs::exists(dir_ / "t.tum.cov.1"));
  EXPECT_FALSE(fs::exists(dir_ / "t.tum.cov.3"));
  // Each pair holds the same poses: the first stamp of t.tum.1 is that of t.tum.cov.1.
  const std::string a = read(dir_ / "t.tum.1");
  const std::string b = read(dir_ / "t.tum.cov.1");
  EXPECT_EQ(a.substr(0, a.find(' ')), b.substr(0, b.find(' ')));
  for (const auto& e : fs::directory_iterator(dir_)) {
    EXPECT_LE(fs::file_size(e.path()), 4000U + 1000U) << e.path();
  }
}

TEST_F(Outputs, DiagnosticsStartEachRotatedFileWithTheHeader) {
  firmware::DiagnosticsCsv csv;
  std::string error;
  ASSERT_TRUE(csv.open((dir_ / "d.csv").string(), error, Rotation{500, 2})) << error;
  for (int i = 0; i < 50; ++i) {
    hal::log::UpdateRecord r{};
    r.t_ns = i;
    csv.update(r);
  }
  ASSERT_TRUE(csv.close());
  EXPECT_EQ(read(dir_ / "d.csv.1").rfind("#t_ns,track_id", 0), 0U);
  EXPECT_EQ(read(dir_ / "d.csv").rfind("#t_ns,track_id", 0), 0U);
  EXPECT_FALSE(fs::exists(dir_ / "d.csv.2"));
}

TEST_F(Outputs, AFailedWriteIsToldWithTheFileAndTheReason) {
  // Without the check, the stdio buffer swallows the error and the run looks complete.
  firmware::TumWriter tum;
  std::string error;
  ASSERT_TRUE(tum.open("/dev/full", false, false, error, Rotation{100, 4})) << error;
  tum.publish(pose(1));
  EXPECT_FALSE(tum.close());
  ASSERT_EQ(tum.errors().size(), 1U);
  EXPECT_EQ(tum.errors()[0], "/dev/full: cannot write: No space left on device");
}

TEST_F(Outputs, TheRecorderBlamesTheDiskNotItsBuffer) {
  firmware::Recorder rec;
  firmware::RecorderOptions o;
  o.path = "/dev/full";
  o.buffer_bytes = 128U << 10;
  std::string error;
  ASSERT_TRUE(rec.open(o, "filter: {}\n", error)) << error;
  for (int i = 0; i < 20000; ++i) {
    rec.gyro(hal::GyroSample{i * 10'000'000LL, 0.1, 0.0, 0.0, false, 0});
    rec.write_some();
  }
  rec.close();
  EXPECT_EQ(rec.stats().dropped_buffer_full, 0U);
  EXPECT_GT(rec.stats().dropped_write_failed, 0U);
  EXPECT_TRUE(contains(rec.write_error(), "/dev/full: cannot write: No space left on device"))
      << rec.write_error();
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  EXPECT_FALSE(firmware::close_and_report_outputs("test", nullptr, nullptr, &rec, out));
  std::fclose(out);
}

TEST(OutputsConfig, SinksRotateByDefaultAndTheKeysAreChecked) {
  const firmware::ConfigResult d = firmware::parse_config("", "c.yaml", {});
  EXPECT_EQ(d.config.sinks.rotation.max_file_bytes, std::size_t{64} << 20);
  EXPECT_EQ(d.config.sinks.rotation.max_files, 4);
  const firmware::ConfigResult r =
      firmware::parse_config("sinks:\n  max_file_mb: 2\n  max_files: 3\n", "c.yaml", {});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.config.sinks.rotation.max_file_bytes, std::size_t{2} << 20);
  EXPECT_EQ(r.config.sinks.rotation.max_files, 3);
  EXPECT_FALSE(firmware::parse_config("sinks:\n  max_files: 0\n", "c.yaml", {}).ok());
}

TEST(OutputsConfig, ASaveIntervalThatWouldSaveEveryIterationIsRefused) {
  const firmware::ConfigResult r =
      firmware::parse_config("", "c.yaml", {"map.save_interval_s=1e-9"});
  ASSERT_EQ(r.errors.size(), 1U);
  EXPECT_TRUE(contains(r.errors[0],
                       "map.save_interval_s: 1e-09 is out of range [0.1, 86400]: a "
                       "save holds the loop"))
      << r.errors[0];
  EXPECT_TRUE(firmware::parse_config("", "c.yaml", {"map.save_interval_s=0.2"}).ok());
}

TEST(OutputsConfig, ACameraThatWouldBlindTheEstimatorIsRefused) {
  const struct {
    const char* set;
    const char* error;
  } cases[] = {
      {"calibration.camera.fx=1e-6",
       "calibration.camera.fx: 1e-06 is out of range [42.87, 1829]: the field of view across "
       "calibration.camera.width 320 px must be 10 to 150 degrees"},
      {"calibration.camera.cx=1e4",
       "calibration.camera.cx: 10000 is out of range [-0.5, 319.5]: the principal point must be "
       "inside the image"},
      {"calibration.camera.width=100",  // fx and cx stay those of a 320 px image
       "calibration.camera.cx: 159.5 is out of range [-0.5, 99.5]"},
      {"calibration.wheels.ticks_per_meter_left=1e-300",
       "calibration.wheels.ticks_per_meter_left: 1e-300 is out of range [100, 1e+07]"},
  };
  for (const auto& c : cases) {
    const firmware::ConfigResult r = firmware::parse_config("", "c.yaml", {c.set});
    std::string all;
    for (const auto& e : r.errors) {
      all += e + "\n";
    }
    EXPECT_TRUE(contains(all, c.error)) << c.set << ":\n" << all;
  }
}

}  // namespace
}  // namespace cleanslam
