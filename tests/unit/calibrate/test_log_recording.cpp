#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "calibrate_log_data.hpp"
#include "calibrate_test_data.hpp"
#include "cleanslam/calibrate/allan_deviation.hpp"
#include "cleanslam/calibrate/camera_calibration.hpp"
#include "cleanslam/calibrate/log_recording.hpp"
#include "cleanslam/calibrate/wheel_calibration.hpp"
#include "cleanslam/readers/log_source.hpp"

using namespace cleanslam;
using namespace cleanslam::calibrate_test;

namespace {

bool mentions(const std::vector<std::string>& lines, const std::string& what) {
  for (const std::string& l : lines) {
    if (l.find(what) != std::string::npos) {
      return true;
    }
  }
  return false;
}

// A log recorded from the simulated calibration drive holds the dataset's samples, so it gives
// the same ticks per metre and wheel base (the log has no sensors.yaml: the wheel base's
// iteration starts elsewhere and settles at the same value).
TEST(LogRecording, WheelsFromALogMatchTheDatasetItWasRecordedFrom) {
  TempDir dir;
  const auto sc = scenario("calibration-wheels", 1);
  const readers::Dataset d = simulated(sc, dir.sub("dataset"));
  record_log(dir.sub("dataset"), dir.sub("drive.log"));
  std::vector<std::string> warnings;
  auto log = calibrate::read_log_samples(dir.sub("drive.log"), warnings);
  ASSERT_TRUE(log.ok()) << log.error();
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(log->gyro.size(), d.gyro.size());
  EXPECT_EQ(log->encoders.size(), d.encoders.size());
  calibrate::WheelCalibrationOptions o;
  o.straight_length_m = sc.path.straight_m;
  auto from_dataset = calibrate::calibrate_wheels(d, o);
  auto from_log = calibrate::calibrate_wheels(*log, o);
  ASSERT_TRUE(from_dataset.ok()) << from_dataset.error();
  ASSERT_TRUE(from_log.ok()) << from_log.error();
  std::printf("dataset: ticks/m %.6f / %.6f, wheel base %.8f m; log: %.6f / %.6f, %.8f m\n",
              from_dataset->ticks_per_meter_left, from_dataset->ticks_per_meter_right,
              from_dataset->wheel_base_m, from_log->ticks_per_meter_left,
              from_log->ticks_per_meter_right, from_log->wheel_base_m);
  EXPECT_LT(
      std::abs(relative_error(from_log->ticks_per_meter_left, from_dataset->ticks_per_meter_left)),
      1e-9);
  EXPECT_LT(std::abs(relative_error(from_log->ticks_per_meter_right,
                                    from_dataset->ticks_per_meter_right)),
            1e-9);
  EXPECT_LT(std::abs(relative_error(from_log->wheel_base_m, from_dataset->wheel_base_m)), 1e-9);
  EXPECT_EQ(from_log->turns, from_dataset->turns);
}

// The same for the gyro's noise on a shortened standstill (--min-duration lowered to fit it).
TEST(LogRecording, GyroNoiseFromALogMatchesTheDatasetItWasRecordedFrom) {
  TempDir dir;
  const readers::Dataset d =
      simulated(scenario("calibration-gyro", 1, {"duration_s=120"}), dir.sub("dataset"));
  record_log(dir.sub("dataset"), dir.sub("standstill.log"));
  std::vector<std::string> warnings;
  auto log = calibrate::read_log_samples(dir.sub("standstill.log"), warnings);
  ASSERT_TRUE(log.ok()) << log.error();
  calibrate::GyroNoiseOptions o;
  o.min_duration_s = 100.0;
  auto from_dataset = calibrate::gyro_noise(d, o);
  auto from_log = calibrate::gyro_noise(*log, o);
  ASSERT_TRUE(from_dataset.ok()) << from_dataset.error();
  ASSERT_TRUE(from_log.ok()) << from_log.error();
  std::printf(
      "dataset: %d samples, noise density %.6g, bias instability %.4g; log: %d, %.6g, "
      "%.4g\n",
      from_dataset->samples, from_dataset->noise_density, from_dataset->bias_instability,
      from_log->samples, from_log->noise_density, from_log->bias_instability);
  EXPECT_EQ(from_log->samples, from_dataset->samples);
  EXPECT_LT(std::abs(relative_error(from_log->noise_density, from_dataset->noise_density)), 1e-9);
  EXPECT_LT(std::abs(relative_error(from_log->bias_instability, from_dataset->bias_instability)),
            1e-9);
}

// The camera from a log of the rendered checkerboard views: within 1 % of the truth, every frame
// used (20 <= 40), or every third when at most 8 are wanted.
TEST(LogRecording, CameraFromALogOfTheRenderedBoardWithinOnePercentOfTheTruth) {
  TempDir dir;
  const auto sc = scenario("calibration-camera", 1);
  simulated(sc, dir.sub("dataset"));
  const std::size_t images = calibrate::image_files(dir.sub("dataset/cam0/data")).size();
  record_log(dir.sub("dataset"), dir.sub("board.log"));
  std::vector<std::string> warnings;
  auto frames = calibrate::read_log_frames(dir.sub("board.log"), 0, 40, warnings);
  ASSERT_TRUE(frames.ok()) << frames.error();
  EXPECT_EQ(frames->every, 1);
  EXPECT_EQ(frames->views.size(), images);
  EXPECT_EQ(static_cast<std::size_t>(frames->frames_with_image), images);
  auto c = calibrate::calibrate_camera(frames->views, board_of(sc), {});
  ASSERT_TRUE(c.ok()) << c.error();
  const std::array<double, 4> e = intrinsics_errors(*c, sc);
  std::printf(
      "log of %zu frames: fx %+.3f %%, fy %+.3f %%, cx %+.3f %%, cy %+.3f %%, RMS %.3f px, "
      "%d views\n",
      images, 100.0 * e[0], 100.0 * e[1], 100.0 * e[2], 100.0 * e[3], c->rms_px, c->views);
  for (const double ei : e) {
    EXPECT_LT(std::abs(ei), 0.01);
  }

  auto thinned = calibrate::read_log_frames(dir.sub("board.log"), 0, 8, warnings);
  ASSERT_TRUE(thinned.ok()) << thinned.error();
  EXPECT_EQ(thinned->every, static_cast<int>((images + 7) / 8));
  EXPECT_LE(thinned->views.size(), 8U);
}

// A later file of a rotated recording is read with a warning saying how to join the files; the
// join reads as the whole recording.
TEST(LogRecording, WarnsOfALaterFileOfARotatedRecording) {
  TempDir dir;
  simulated(scenario("calibration-camera", 1), dir.sub("dataset"));
  const std::size_t images = calibrate::image_files(dir.sub("dataset/cam0/data")).size();
  const std::string log = dir.sub("board.log");
  record_log(dir.sub("dataset"), log, {"recorder.max_file_mb=1"});
  ASSERT_TRUE(std::filesystem::exists(log + ".1"));
  ASSERT_FALSE(std::filesystem::exists(log + ".2"));
  std::vector<std::string> warnings;
  auto later = calibrate::read_log_frames(log, 0, 40, warnings);
  ASSERT_TRUE(later.ok()) << later.error();
  EXPECT_LT(later->views.size(), images);
  EXPECT_TRUE(mentions(warnings, log + " is file 1 of a rotated recording"))
      << (warnings.empty() ? "no warning" : warnings.front());
  EXPECT_TRUE(mentions(warnings, "cat " + log + ".1 " + log + " > joined.log"));

  const std::string joined = dir.sub("joined.log");
  {
    std::ofstream out(joined, std::ios::binary);
    out << std::ifstream(log + ".1", std::ios::binary).rdbuf()
        << std::ifstream(log, std::ios::binary).rdbuf();
  }
  warnings.clear();
  auto whole = calibrate::read_log_frames(joined, 0, 40, warnings);
  ASSERT_TRUE(whole.ok()) << whole.error();
  EXPECT_EQ(whole->views.size(), images);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
}

TEST(LogRecording, RefusesFramesWithoutImagesSayingHowToRecordThem) {
  TempDir dir;
  // The drive's camera gives features only (the simulator's front end), no image.
  simulated(scenario("calibration-wheels", 1), dir.sub("dataset"));
  record_log(dir.sub("dataset"), dir.sub("drive.log"));
  std::vector<std::string> warnings;
  auto frames = calibrate::read_log_frames(dir.sub("drive.log"), 0, 40, warnings);
  ASSERT_FALSE(frames.ok());
  EXPECT_NE(frames.error().find(dir.sub("drive.log") + ": none of its"), std::string::npos)
      << frames.error();
  EXPECT_NE(frames.error().find("recorder.frame_every 1"), std::string::npos) << frames.error();

  record_log(dir.sub("dataset"), dir.sub("no_frames.log"), {"recorder.frame_every=0"});
  auto none = calibrate::read_log_frames(dir.sub("no_frames.log"), 0, 40, warnings);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().find("no frame record"), std::string::npos) << none.error();
}

TEST(LogRecording, RefusesAFileThatIsNotALogNamingIt) {
  TempDir dir;
  std::filesystem::create_directories(dir.str());
  const std::string path = dir.sub("notes.txt");
  std::ofstream(path) << "not a log at all\n";
  std::vector<std::string> warnings;
  auto samples = calibrate::read_log_samples(path, warnings);
  ASSERT_FALSE(samples.ok());
  EXPECT_NE(samples.error().find(path + ": not a cleanslam log"), std::string::npos)
      << samples.error();
  auto frames = calibrate::read_log_frames(path, 0, 40, warnings);
  ASSERT_FALSE(frames.ok());
  EXPECT_NE(frames.error().find(path), std::string::npos) << frames.error();
}

// A damaged record is refused and counted; the rest is read.
TEST(LogRecording, CountsTheRecordsADamagedLogRefusesAndGoesOn) {
  TempDir dir;
  const readers::Dataset d =
      simulated(scenario("calibration-gyro", 1, {"duration_s=20"}), dir.sub("dataset"));
  const std::string path = dir.sub("standstill.log");
  record_log(dir.sub("dataset"), path);
  {
    // A byte of the middle gyro record's payload flipped: its checksum fails.
    readers::LogReader reader;
    ASSERT_TRUE(reader.open(path)) << reader.error();
    std::vector<std::size_t> gyro;
    for (const readers::LogRecordRef& r : reader.records()) {
      if (r.type == hal::log::RecordType::kGyro) {
        gyro.push_back(r.offset);
      }
    }
    ASSERT_FALSE(gyro.empty());
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(gyro[gyro.size() / 2] + hal::log::kRecordHeaderSize + 1));
    f.put('\x5a');
  }
  std::vector<std::string> warnings;
  auto log = calibrate::read_log_samples(path, warnings);
  ASSERT_TRUE(log.ok()) << log.error();
  EXPECT_TRUE(mentions(warnings, path + ": 1 ")) << (warnings.empty() ? "none" : warnings.front());
  EXPECT_TRUE(mentions(warnings, "record(s) refused"));
  EXPECT_EQ(log->gyro.size() + 1, d.gyro.size());
  EXPECT_EQ(log->encoders.size(), d.encoders.size());
}

// A log with neither gyro nor encoder record is refused, naming it.
TEST(LogRecording, RefusesALogWithoutSamplesNamingIt) {
  TempDir dir;
  simulated(scenario("calibration-gyro", 1, {"duration_s=5"}), dir.sub("dataset"));
  const std::string path = dir.sub("standstill.log");
  record_log(dir.sub("dataset"), path);
  // Only the file header and the configuration record are kept.
  readers::LogReader reader;
  ASSERT_TRUE(reader.open(path)) << reader.error();
  std::filesystem::resize_file(path, reader.records().at(1).offset);
  std::vector<std::string> warnings;
  auto log = calibrate::read_log_samples(path, warnings);
  ASSERT_FALSE(log.ok());
  EXPECT_NE(log.error().find(path + ": no gyro or encoder record"), std::string::npos)
      << log.error();
}

}  // namespace
