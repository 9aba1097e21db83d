#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/dataset_source.hpp"
#include "cleanslam/readers/gray_image.hpp"
#include "cleanslam/sim_hal/dataset_writer.hpp"
#include "cleanslam/sim_hal/gray_image_writer.hpp"
#include "sim_test_files.hpp"
#include "text_checks.hpp"

namespace fs = std::filesystem;
using namespace cleanslam;
using readers::DatasetSource;
using sim_hal::DatasetWriter;
using sim_test::load_error;
using test::contains;

namespace {

class DatasetDir {
 public:
  DatasetDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / (std::string("cleanslam_ds_") + info->test_suite_name() +
                                         "_" + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~DatasetDir() { fs::remove_all(path_); }
  [[nodiscard]] const fs::path& path() const { return path_; }
  [[nodiscard]] std::string str() const { return path_.string(); }

 private:
  fs::path path_;
};

readers::GrayImage pattern(int w, int h, int seed) {
  readers::GrayImage img(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      img.at(x, y) = static_cast<std::uint8_t>((x * 7 + y * 3 + seed) & 0xFF);
    }
  }
  return img;
}

void write_file(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void replace_in_file(const fs::path& p, const std::string& from, const std::string& to) {
  std::string s = read_file(p);
  const auto pos = s.find(from);
  ASSERT_NE(pos, std::string::npos) << from;
  s.replace(pos, from.size(), to);
  write_file(p, s);
}

// A small dataset: 1 s of gyro at 100 Hz, encoders at 20 Hz, images at 0.25 s and 0.75 s,
// features at 0.25 s (with the image) and 0.5 s (alone), ground truth at 10 Hz.
void make_dataset(const std::string& folder, int width = 32, int height = 24,
                  DatasetWriter::ImageFormat format = DatasetWriter::ImageFormat::kPng) {
  hal::Calibration cal;
  cal.camera.width = width;
  cal.camera.height = height;
  // The default camera's field of view and principal point, scaled to this image.
  cal.camera.fx = cal.camera.fy = 280.0 * width / 320.0;
  cal.camera.cx = 0.5 * (width - 1);
  cal.camera.cy = 0.5 * (height - 1);
  DatasetWriter w;
  ASSERT_TRUE(w.open(folder, cal, format).ok());
  for (int i = 0; i < 100; ++i) {
    w.add_gyro(hal::GyroSample{i * 10 * hal::kNsPerMillisecond, 0.01 * i, 0, 0, false, 0});
  }
  for (int i = 0; i < 20; ++i) {
    // Counters near the 32-bit limits, wrapping (computed without signed overflow).
    const auto step = static_cast<std::uint32_t>(10 * i);
    w.add_encoder(hal::EncoderSample{i * 50 * hal::kNsPerMillisecond + 1,
                                     static_cast<std::int32_t>(2147483600U + step),
                                     static_cast<std::int32_t>(2147483696U - step), 0});
  }
  ASSERT_TRUE(w.add_image(250 * hal::kNsPerMillisecond, pattern(width, height, 1).view()).ok());
  ASSERT_TRUE(w.add_image(750 * hal::kNsPerMillisecond, pattern(width, height, 2).view()).ok());
  const hal::FeatureObservation f1[] = {{3, 10.5, 11.25}, {7, 1.0, 2.0}};
  const hal::FeatureObservation f2[] = {{3, 12.5, 11.0}};
  w.add_features(250 * hal::kNsPerMillisecond, f1, 2);
  w.add_features(500 * hal::kNsPerMillisecond, f2, 1);
  for (int i = 0; i < 10; ++i) {
    w.add_groundtruth(readers::GroundTruthPose{
        i * 100 * hal::kNsPerMillisecond, {0.1 * i, 0.0, 0.0}, {1.0, 0.0, 0.0, 0.0}});
  }
  ASSERT_TRUE(w.close().ok());
}

}  // namespace

TEST(Dataset, WriterAndReaderRoundTrip) {
  DatasetDir dir;
  make_dataset(dir.str());
  auto d = readers::load_dataset(dir.str());
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_TRUE(d->warnings.empty());
  ASSERT_EQ(d->gyro.size(), 100U);
  EXPECT_DOUBLE_EQ(d->gyro[37].wz_rad_s, 0.37);
  ASSERT_EQ(d->encoders.size(), 20U);
  ASSERT_EQ(d->camera.size(), 2U);
  ASSERT_EQ(d->features.size(), 3U);
  EXPECT_EQ(d->features[1].observation.track_id, 7);
  EXPECT_DOUBLE_EQ(d->features[0].observation.v_px, 11.25);
  ASSERT_EQ(d->groundtruth.size(), 10U);
  EXPECT_DOUBLE_EQ(d->groundtruth[3].position_m[0], 0.1 * 3);
  EXPECT_EQ(d->calibration.camera.width, 32);
  EXPECT_EQ(d->calibration.camera.T_body_cam, hal::Calibration{}.camera.T_body_cam);
}

TEST(Dataset, TickWrapAroundPassesThroughUnchanged) {
  DatasetDir dir;
  make_dataset(dir.str());
  auto d = readers::load_dataset(dir.str());
  ASSERT_TRUE(d.ok()) << d.error();
  // 2147483600 + 10 * 19 wraps past INT32_MAX.
  for (std::size_t i = 0; i < d->encoders.size(); ++i) {
    const int k = static_cast<int>(i);
    EXPECT_EQ(d->encoders[i].left_ticks, static_cast<std::int32_t>(static_cast<std::uint32_t>(
                                             2147483600U + 10U * static_cast<unsigned>(k))));
  }
  EXPECT_LT(d->encoders[19].left_ticks, 0);
  EXPECT_GT(d->encoders[19].right_ticks, 0);
  EXPECT_EQ(hal::tick_delta(d->encoders[19].left_ticks, d->encoders[0].left_ticks), 190);
  EXPECT_EQ(hal::tick_delta(d->encoders[19].right_ticks, d->encoders[0].right_ticks), -190);
  // Written as unsigned 32-bit values they wrap to the same counters.
  write_file(dir.path() / "encoders.csv",
             "#t_ns,left_ticks,right_ticks\n0,4294967295,-2147483648\n5,2147483647,0\n");
  auto e = readers::read_encoders_csv((dir.path() / "encoders.csv").string());
  ASSERT_TRUE(e.ok()) << e.error();
  EXPECT_EQ((*e)[0].left_ticks, -1);
  EXPECT_EQ((*e)[0].right_ticks, INT32_MIN);
  EXPECT_EQ((*e)[1].left_ticks, INT32_MAX);
  write_file(dir.path() / "encoders.csv", "#t_ns,left_ticks,right_ticks\n0,4294967296,0\n");
  EXPECT_TRUE(contains(load_error(dir.str()), "encoders.csv:2: left_ticks:"));
}

TEST(Dataset, MissingRequiredFile) {
  for (const char* name : {"sensors.yaml", "gyro.csv", "encoders.csv"}) {
    DatasetDir dir;
    make_dataset(dir.str());
    fs::remove(dir.path() / name);
    const std::string e = load_error(dir.str());
    EXPECT_TRUE(contains(e, name) && contains(e, "cannot open")) << e;
  }
  DatasetDir dir;
  make_dataset(dir.str());
  fs::remove_all(dir.path() / "cam0");
  fs::remove(dir.path() / "features.csv");
  EXPECT_TRUE(contains(load_error(dir.str()), "neither cam0/data.csv nor features.csv"));
  EXPECT_TRUE(contains(load_error((dir.path() / "nope").string()), "not a dataset folder"));
}

TEST(Dataset, BadHeader) {
  DatasetDir dir;
  make_dataset(dir.str());
  replace_in_file(dir.path() / "gyro.csv", "#t_ns,wz_rad_s", "#t_ns,wz");
  const std::string e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "gyro.csv:1: expected the header \"#t_ns,wz_rad_s\"")) << e;
  DatasetDir dir2;
  make_dataset(dir2.str());
  replace_in_file(dir2.path() / "encoders.csv", "#t_ns,", "t_ns,");
  EXPECT_TRUE(contains(load_error(dir2.str()), "encoders.csv:1: expected the header"));
}

TEST(Dataset, NonNumericAndWrongFieldCount) {
  DatasetDir dir;
  make_dataset(dir.str());
  replace_in_file(dir.path() / "gyro.csv", "\n20000000,0.02\n", "\n20000000,abc\n");
  std::string e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "gyro.csv:4: wz_rad_s: expected a finite number, got \"abc\"")) << e;
  replace_in_file(dir.path() / "gyro.csv", "\n20000000,abc\n", "\n20000000,nan\n");
  e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "gyro.csv:4: wz_rad_s:")) << e;
  replace_in_file(dir.path() / "gyro.csv", "\n20000000,nan\n", "\n20000000,1,2\n");
  e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "gyro.csv:4: expected 2 fields, got 3")) << e;
  replace_in_file(dir.path() / "gyro.csv", "\n20000000,1,2\n", "\n20000000,0.02\n");
  replace_in_file(dir.path() / "features.csv", "\n250000000,7,", "\n250000000,-7,");
  e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "features.csv:3: track_id: track id must be non-negative")) << e;
  replace_in_file(dir.path() / "features.csv", "\n250000000,-7,", "\n25e7,7,");
  e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "features.csv:3: t_ns: expected an integer, got \"25e7\"")) << e;
}

TEST(Dataset, UnsortedTimeStamps) {
  DatasetDir dir;
  make_dataset(dir.str());
  replace_in_file(dir.path() / "encoders.csv", "\n100000001,", "\n1,");
  const std::string e = load_error(dir.str());
  EXPECT_TRUE(
      contains(e, "encoders.csv:4: t_ns: time stamp 1 is not after the previous row's 50000001"))
      << e;
  DatasetDir dir2;
  make_dataset(dir2.str());
  replace_in_file(dir2.path() / "groundtruth.csv", "\n200000000,", "\n100000000,");
  EXPECT_TRUE(contains(load_error(dir2.str()), "groundtruth.csv:4: t_ns: time stamp"));
}

TEST(Dataset, ImageNamesStayInsideCam0Data) {
  DatasetDir dir;
  make_dataset(dir.str());
  replace_in_file(dir.path() / "cam0" / "data.csv", ",750000000.png", ",../../gyro.csv");
  const std::string e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "cam0/data.csv:3: filename: file name must be relative")) << e;
  fs::create_directories(dir.path() / "cam0" / "data" / "a..b");
  fs::rename(dir.path() / "cam0" / "data" / "750000000.png",
             dir.path() / "cam0" / "data" / "a..b" / "x..png");
  replace_in_file(dir.path() / "cam0" / "data.csv", ",../../gyro.csv", ",a..b/x..png");
  EXPECT_EQ(load_error(dir.str()), "");
}

TEST(Dataset, MissingImage) {
  DatasetDir dir;
  make_dataset(dir.str());
  fs::remove(dir.path() / "cam0" / "data" / "750000000.png");
  const std::string e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "cam0/data.csv:3: filename:") && contains(e, "image not found")) << e;
}

TEST(Dataset, WrongImageSize) {
  DatasetDir dir;
  make_dataset(dir.str());
  ASSERT_TRUE(sim_hal::write_png((dir.path() / "cam0" / "data" / "250000000.png").string(),
                                 pattern(16, 24, 0).view())
                  .ok());
  const std::string e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "cam0/data.csv:2: filename:") &&
              contains(e, "image is 16x24, sensors.yaml says 32x24"))
      << e;
  write_file(dir.path() / "cam0" / "data" / "250000000.png", "not an image at all");
  EXPECT_TRUE(contains(load_error(dir.str()), "not a binary PGM (P5) or PNG image"));
}

TEST(Dataset, MissingRequiredYamlKey) {
  DatasetDir dir;
  make_dataset(dir.str());
  replace_in_file(dir.path() / "sensors.yaml", "  fy: 28.0\n", "");
  std::string e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "sensors.yaml:2: camera.fy: missing required key")) << e;
  replace_in_file(dir.path() / "sensors.yaml", "  wheel_base: 0.235\n", "  wheel_base: wide\n");
  e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "camera.fy: missing required key")) << e;
  EXPECT_TRUE(contains(e, "wheels.wheel_base: expected a number, got \"wide\"")) << e;
}

TEST(Dataset, UnknownYamlKeyIsAnError) {
  DatasetDir dir;
  make_dataset(dir.str());
  replace_in_file(dir.path() / "sensors.yaml", "gyro:\n", "gyro:\n  colour: blue\n");
  const std::string e = load_error(dir.str());
  EXPECT_TRUE(contains(e, "gyro.colour: unknown key")) << e;
}

TEST(Dataset, BadTransformIsRefused) {
  DatasetDir dir;
  make_dataset(dir.str());
  replace_in_file(dir.path() / "sensors.yaml", "[0.0, 0.0, 1.0, 0.1,", "[0.0, 0.0, 2.0, 0.1,");
  EXPECT_TRUE(
      contains(load_error(dir.str()), "camera.T_body_cam: rotation block is not orthonormal"));
}

TEST(Dataset, CameraFarFromTheBodyIsRefused) {
  DatasetDir dir;
  make_dataset(dir.str());
  replace_in_file(dir.path() / "sensors.yaml", "[0.0, 0.0, 1.0, 0.1,", "[0.0, 0.0, 1.0, 1e7,");
  EXPECT_TRUE(contains(load_error(dir.str()),
                       "camera.T_body_cam: translation more than 10 m from the body's origin"));
}

// Each of these went through before (a run with a negative noise, or with every prediction
// refused): a calibration number outside hal::calibration_limits is an error naming line and key.
TEST(Dataset, CalibrationNumbersOutsideTheirLimitsAreRefused) {
  const struct {
    const char* written;
    const char* replaced_by;
    const char* error;
  } cases[] = {
      {"pixel_noise: 0.5", "pixel_noise: -3", "camera.pixel_noise: -3 is out of range (0, 100]"},
      {"time_offset_s: 0.0", "time_offset_s: 1e12",
       "camera.time_offset_s: 1e+12 is out of range [-1, 1]"},
      {"fx: 280.0", "fx: 1e300", "camera.fx: 1e+300 is out of range [42.87, 1829]"},
      {"cx: 159.5", "cx: -1e300", "camera.cx: -1e+300 is out of range [-0.5, 319.5]"},
      {"fx: 280.0", "fx: 1e-6",
       "camera.fx: 1e-06 is out of range [42.87, 1829]: the field of view across camera.width "
       "320 px must be 10 to 150 degrees"},
      {"cx: 159.5", "cx: 1e4",
       "camera.cx: 10000 is out of range [-0.5, 319.5]: the principal point must be inside the "
       "image (camera.width 320 px)"},
      {"width: 320", "width: 16384",
       "camera.width: 16384 is out of range [1, 320]: the front end takes images of at most "
       "320x240 pixels"},
      {"ticks_per_meter_left: 4000.0", "ticks_per_meter_left: 1e-300",
       "wheels.ticks_per_meter_left: 1e-300 is out of range [100, 1e+07]"},
      {"distortion: [0.0, 0.0, 0.0, 0.0]", "distortion: [0.0, 0.0, 1e300, 0.0]",
       "camera.distortion: 1e+300 is out of range [-100, 100]"},
      {"wheel_base: 0.235", "wheel_base: 0", "wheels.wheel_base: 0 is out of range (0, 10]"},
      {"distance_noise: 0.02", "distance_noise: 1e300",
       "wheels.distance_noise: 1e+300 is out of range [0, 1]"},
      {"noise_density: 0.0005", "noise_density: -1",
       "gyro.noise_density: -1 is out of range (0, 1]"},
      {"bias_instability: 0.0001", "bias_instability: -5",
       "gyro.bias_instability: -5 is out of range [0, 1]"},
  };
  for (const auto& c : cases) {
    DatasetDir dir;
    make_dataset(dir.str(), 320, 240);
    replace_in_file(dir.path() / "sensors.yaml", c.written, c.replaced_by);
    const std::string e = load_error(dir.str());
    EXPECT_TRUE(contains(e, "sensors.yaml:")) << e;
    EXPECT_TRUE(contains(e, c.error)) << c.replaced_by << ": " << e;
  }
}

TEST(Dataset, ImagesRoundTripAsPgmAndPng) {
  DatasetDir dir;
  const auto img = pattern(40, 30, 5);
  for (const char* name : {"a.pgm", "a.png"}) {
    const std::string p = (dir.path() / name).string();
    const bool png = std::string(name).ends_with("png");
    ASSERT_TRUE((png ? sim_hal::write_png(p, img.view()) : sim_hal::write_pgm(p, img.view())).ok());
    readers::GrayImage back;
    ASSERT_TRUE(readers::read_gray_image(p, back).ok());
    EXPECT_EQ(back.width, 40);
    EXPECT_EQ(back.height, 30);
    EXPECT_EQ(back.pixels, img.pixels);
    auto size = readers::read_gray_image_size(p);
    ASSERT_TRUE(size.ok());
    EXPECT_EQ(size->width, 40);
  }
  write_file(dir.path() / "c.pgm", "P5\n# comment\n4 2\n255\nabcdefg");
  readers::GrayImage back;
  auto s = readers::read_gray_image((dir.path() / "c.pgm").string(), back);
  EXPECT_TRUE(!s.ok() && contains(s.error(), "truncated"));
  write_file(dir.path() / "c.pgm", "P5\n4 2\n65535\nabcdefgh");
  s = readers::read_gray_image((dir.path() / "c.pgm").string(), back);
  EXPECT_TRUE(!s.ok() && contains(s.error(), "not 8-bit"));
  write_file(dir.path() / "c.pgm", "P5\n# comment\n4 2\n255\nabcdefgh");
  s = readers::read_gray_image((dir.path() / "c.pgm").string(), back);
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(back.at(3, 1), 'h');
}

TEST(DatasetSource, MergesInTimeOrderWithFrames) {
  DatasetDir dir;
  make_dataset(dir.str(), 32, 24, DatasetWriter::ImageFormat::kPgm);
  auto src = DatasetSource::open(dir.str());
  ASSERT_TRUE(src.ok()) << src.error();
  EXPECT_EQ(src->frame_count(), 3U);
  hal::SensorEvent ev;
  hal::TimeNs last = -1;
  int gyro = 0, enc = 0, frames = 0;
  while (src->read(ev)) {
    hal::TimeNs t = 0;
    switch (ev.kind) {
      case hal::SensorEvent::Kind::kGyro:
        t = ev.gyro.t_ns;
        ++gyro;
        break;
      case hal::SensorEvent::Kind::kEncoder:
        t = ev.encoder.t_ns;
        ++enc;
        break;
      case hal::SensorEvent::Kind::kFrame: {
        t = ev.frame.t_ns;
        ++frames;
        if (t == 250 * hal::kNsPerMillisecond) {
          ASSERT_TRUE(ev.frame.has_image());
          EXPECT_EQ(ev.frame.image.at(2, 1), pattern(32, 24, 1).at(2, 1));
          ASSERT_EQ(ev.frame.feature_count, 2);
          EXPECT_EQ(ev.frame.features[1].track_id, 7);
        } else if (t == 500 * hal::kNsPerMillisecond) {
          EXPECT_FALSE(ev.frame.has_image());
          ASSERT_EQ(ev.frame.feature_count, 1);
          EXPECT_DOUBLE_EQ(ev.frame.features[0].u_px, 12.5);
        } else {
          EXPECT_EQ(t, 750 * hal::kNsPerMillisecond);
          ASSERT_TRUE(ev.frame.has_image());
          EXPECT_FALSE(ev.frame.has_features());
          EXPECT_EQ(ev.frame.image.at(5, 3), pattern(32, 24, 2).at(5, 3));
        }
        break;
      }
      default:
        FAIL();
    }
    EXPECT_GE(t, last);
    last = t;
  }
  EXPECT_EQ(gyro, 100);
  EXPECT_EQ(enc, 20);
  EXPECT_EQ(frames, 3);
  EXPECT_TRUE(src->exhausted());
  EXPECT_EQ(src->next_event_time(), -1);
  EXPECT_EQ(src->image_errors(), 0);
}

TEST(DatasetSource, LoadsEachImageWhenItIsItsTurn) {
  DatasetDir dir;
  make_dataset(dir.str());
  auto src = DatasetSource::open(dir.str());
  ASSERT_TRUE(src.ok()) << src.error();
  // Replaced after open: the source must read the new pixels, so it did not preload them.
  ASSERT_TRUE(sim_hal::write_png((dir.path() / "cam0" / "data" / "750000000.png").string(),
                                 readers::GrayImage(32, 24, 99).view())
                  .ok());
  hal::SensorEvent ev;
  bool seen = false;
  while (src->read(ev)) {
    if (ev.kind == hal::SensorEvent::Kind::kFrame &&
        ev.frame.t_ns == 750 * hal::kNsPerMillisecond) {
      ASSERT_TRUE(ev.frame.has_image());
      EXPECT_EQ(ev.frame.image.at(10, 10), 99);
      seen = true;
    }
  }
  EXPECT_TRUE(seen);
}

TEST(DatasetSource, ImageVanishingWhileStreamingIsCountedNotFatal) {
  DatasetDir dir;
  make_dataset(dir.str());
  auto src = DatasetSource::open(dir.str());
  ASSERT_TRUE(src.ok());
  fs::remove(dir.path() / "cam0" / "data" / "750000000.png");
  hal::SensorEvent ev;
  int frames = 0;
  while (src->read(ev)) {
    frames += ev.kind == hal::SensorEvent::Kind::kFrame ? 1 : 0;
  }
  EXPECT_EQ(frames, 3);
  EXPECT_EQ(src->image_errors(), 1);
  EXPECT_TRUE(contains(src->last_error(), "750000000.png"));
}

TEST(DatasetSource, LiftEventsFromLiftCsv) {
  DatasetDir dir;
  make_dataset(dir.str());
  write_file(dir.path() / "lift.csv", "#t_ns,lifted\n300000000,1\n600000000,0\n");
  auto src = DatasetSource::open(dir.str());
  ASSERT_TRUE(src.ok()) << src.error();
  hal::SensorEvent ev;
  std::vector<std::pair<hal::TimeNs, bool>> lifts;
  hal::TimeNs t_before = -1;
  while (true) {
    const hal::TimeNs t = src->next_event_time();
    if (!src->read(ev)) {
      break;
    }
    EXPECT_GE(t, t_before);
    t_before = t;
    if (ev.kind == hal::SensorEvent::Kind::kLift) {
      lifts.emplace_back(t, ev.lifted);
    }
  }
  ASSERT_EQ(lifts.size(), 2U);
  EXPECT_EQ(lifts[0], std::make_pair(hal::TimeNs{300000000}, true));
  EXPECT_EQ(lifts[1], std::make_pair(hal::TimeNs{600000000}, false));
  write_file(dir.path() / "lift.csv", "#t_ns,lifted\n300000000,2\n");
  EXPECT_TRUE(contains(load_error(dir.str()), "lift.csv:2: lifted: expected 0 or 1, got 2"));
}

TEST(DatasetSource, AppliesTheCameraTimeOffsetOnlyWhenAsked) {
  DatasetDir dir;
  make_dataset(dir.str());
  replace_in_file(dir.path() / "sensors.yaml", "time_offset_s: 0.0", "time_offset_s: -0.1");
  for (bool apply : {false, true}) {
    DatasetSource::Options options;
    options.apply_time_offset = apply;
    auto src = DatasetSource::open(dir.str(), options);
    ASSERT_TRUE(src.ok()) << src.error();
    EXPECT_DOUBLE_EQ(src->calibration().camera.time_offset_s, -0.1);
    hal::SensorEvent ev;
    std::vector<hal::TimeNs> frames;
    hal::TimeNs previous = -1;
    while (true) {
      const hal::TimeNs t = src->next_event_time();
      if (!src->read(ev)) {
        break;
      }
      EXPECT_GE(t, previous);
      previous = t;
      if (ev.kind == hal::SensorEvent::Kind::kFrame) {
        frames.push_back(ev.frame.t_ns);
      }
    }
    const hal::TimeNs shift = apply ? -100 * hal::kNsPerMillisecond : 0;
    EXPECT_EQ(frames, (std::vector<hal::TimeNs>{250 * hal::kNsPerMillisecond + shift,
                                                500 * hal::kNsPerMillisecond + shift,
                                                750 * hal::kNsPerMillisecond + shift}));
  }
}

TEST(DatasetSource, IsDeterministic) {
  DatasetDir dir;
  make_dataset(dir.str());
  auto a = DatasetSource::open(dir.str());
  auto b = DatasetSource::open(dir.str());
  ASSERT_TRUE(a.ok() && b.ok());
  hal::SensorEvent ea, eb;
  int n = 0;
  while (a->read(ea)) {
    ASSERT_TRUE(b->read(eb));
    ASSERT_EQ(ea.kind, eb.kind);
    EXPECT_EQ(ea.gyro.t_ns, eb.gyro.t_ns);
    EXPECT_EQ(ea.encoder.t_ns, eb.encoder.t_ns);
    EXPECT_EQ(ea.frame.t_ns, eb.frame.t_ns);
    ++n;
  }
  EXPECT_FALSE(b->read(eb));
  EXPECT_EQ(n, 123);
}

// Garbled files are refused or read, never a crash (run under ASan/UBSan too).
TEST(Dataset, GarbledFilesNeverCrash) {
  DatasetDir dir;
  make_dataset(dir.str(), 32, 24, DatasetWriter::ImageFormat::kPgm);
  const std::vector<fs::path> files = {dir.path() / "sensors.yaml",
                                       dir.path() / "gyro.csv",
                                       dir.path() / "encoders.csv",
                                       dir.path() / "features.csv",
                                       dir.path() / "groundtruth.csv",
                                       dir.path() / "cam0" / "data.csv",
                                       dir.path() / "cam0" / "data" / "250000000.pgm"};
  std::vector<std::string> originals;
  for (const auto& f : files) {
    originals.push_back(read_file(f));
  }
  std::uint64_t state = 12345;
  auto next = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return state >> 33;
  };
  const char kBytes[] = {',', '\n', '#', '-', '9', 'e', '.', ' ', ':', '[', '\0', '\xff', 'P'};
  int refused = 0;
  for (int round = 0; round < 300; ++round) {
    const std::size_t k = next() % files.size();
    std::string s = originals[k];
    const int edits = 1 + static_cast<int>(next() % 4);
    for (int e = 0; e < edits && !s.empty(); ++e) {
      const std::size_t pos = next() % s.size();
      switch (next() % 3) {
        case 0:
          s[pos] = kBytes[next() % sizeof(kBytes)];
          break;
        case 1:
          s.erase(pos, 1 + next() % 8);
          break;
        default:
          s.resize(pos);
          break;
      }
    }
    write_file(files[k], s);
    auto src = DatasetSource::open(dir.str());
    if (src.ok()) {
      hal::SensorEvent ev;
      while (src->read(ev)) {
      }
    } else {
      ++refused;
      EXPECT_FALSE(src.error().empty());
    }
    write_file(files[k], originals[k]);
  }
  EXPECT_GT(refused, 100);
}

// A stamp far in the future costs its row, told with the file and line; the rest is read.
TEST(Dataset, RowsStampedPastTheSpanAreRefusedAndTold) {
  for (const std::string stamp :
       {"9223372036854775807", "9000000000000000000", "31536000010000000"}) {
    DatasetDir dir;
    make_dataset(dir.str());
    replace_in_file(dir.path() / "gyro.csv", "\n500000000,", "\n" + stamp + ",");
    auto d = readers::load_dataset(dir.str());
    ASSERT_TRUE(d.ok()) << d.error();
    EXPECT_EQ(d->gyro.size(), 99U) << stamp;
    EXPECT_EQ(d->rows_refused, 1U) << stamp;
    ASSERT_EQ(d->warnings.size(), 1U) << stamp;
    EXPECT_TRUE(contains(d->warnings[0], "gyro.csv:52: t_ns: time stamp " + stamp +
                                             " is more than 86400.0 s (loop.max_span_s) after "
                                             "the file's first row: row refused"))
        << d->warnings[0];
  }
  DatasetDir dir;
  make_dataset(dir.str());
  replace_in_file(dir.path() / "encoders.csv", "\n50000001,", "\n-9223372036854775808,");
  EXPECT_TRUE(contains(load_error(dir.str()), "encoders.csv:3: t_ns: negative time stamp"));
}

TEST(DatasetSource, AStampOfTheMaximumTimeIsReadNotOverrun) {
  DatasetDir dir;
  make_dataset(dir.str());
  write_file(dir.path() / "gyro.csv",
             read_file(dir.path() / "gyro.csv") + "9223372036854775807,0.5\n");
  DatasetSource::Options options;
  options.load.max_span_ns = hal::kTimeMax;  // let the stamp through to the source
  auto src = DatasetSource::open(dir.str(), options);
  ASSERT_TRUE(src.ok()) << src.error();
  hal::SensorEvent ev;
  int gyro = 0;
  hal::TimeNs last = -1;
  while (src->read(ev)) {
    if (ev.kind == hal::SensorEvent::Kind::kGyro) {
      ++gyro;
      last = ev.gyro.t_ns;
    }
  }
  EXPECT_EQ(gyro, 101);
  EXPECT_EQ(last, hal::kTimeMax);
  EXPECT_TRUE(src->exhausted());
  EXPECT_EQ(src->next_event_time(), -1);
}

TEST(Dataset, ALastLineWithoutLineEndIsSkippedAndTold) {
  DatasetDir dir;
  make_dataset(dir.str());
  std::string enc = read_file(dir.path() / "encoders.csv");
  enc.resize(enc.size() - 4);  // the last row's right ticks cut short
  write_file(dir.path() / "encoders.csv", enc);
  auto d = readers::load_dataset(dir.str());
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ(d->encoders.size(), 19U);
  ASSERT_EQ(d->warnings.size(), 1U);
  EXPECT_TRUE(contains(d->warnings[0],
                       "encoders.csv:21: the last line has no line end: the file was cut short"))
      << d->warnings[0];
}

TEST(DatasetSource, UnreadableImagesAreNamedWithTheirLine) {
  DatasetDir dir;
  make_dataset(dir.str());
  auto src = DatasetSource::open(dir.str());
  ASSERT_TRUE(src.ok()) << src.error();
  const std::string png = (dir.path() / "cam0" / "data" / "750000000.png").string();
  std::string bytes = read_file(png);
  bytes.replace(bytes.size() / 2, 8, "XXXXXXXX");
  write_file(png, bytes);
  hal::SensorEvent ev;
  while (src->read(ev)) {
  }
  EXPECT_EQ(src->image_errors(), 1);
  ASSERT_EQ(src->image_error_messages().size(), 1U);
  EXPECT_TRUE(contains(src->image_error_messages()[0], "cam0/data.csv:3: filename: " + png))
      << src->image_error_messages()[0];
}

TEST(Dataset, ACameraTimeOffsetBeyondHalfASecondIsAWarning) {
  DatasetDir dir;
  make_dataset(dir.str());
  replace_in_file(dir.path() / "sensors.yaml", "time_offset_s: 0.0", "time_offset_s: -0.75");
  auto d = readers::load_dataset(dir.str());
  ASSERT_TRUE(d.ok()) << d.error();
  ASSERT_EQ(d->warnings.size(), 1U);
  EXPECT_TRUE(contains(d->warnings[0], "camera.time_offset_s: -0.75 s is more than 0.5 s"))
      << d->warnings[0];
}

// Rows are read when they fall due: a file that changes after open() so that a row no longer
// reads ends every stream at that row, with the message open() would have given.
TEST(DatasetSource, ARowBrokenAfterOpenEndsTheStreamWithItsLine) {
  DatasetDir dir;
  make_dataset(dir.str());
  std::string gyro = "#t_ns,wz_rad_s\n";
  for (int i = 0; i < 5000; ++i) {
    gyro += std::to_string(hal::TimeNs{i} * 10 * hal::kNsPerMillisecond) + ",0.5\n";
  }
  write_file(dir.path() / "gyro.csv", gyro);
  auto src = DatasetSource::open(dir.str());
  ASSERT_TRUE(src.ok()) << src.error();
  EXPECT_EQ(src->summary().last_ns, 49990 * hal::kNsPerMillisecond);
  EXPECT_TRUE(src->stream_error().empty());
  // The 4000th row (line 4001), in place, far past what a file buffer holds ahead.
  const std::string row = "\n39990000000,0.5\n";
  ASSERT_NE(gyro.find(row), std::string::npos);
  gyro.replace(gyro.find(row), row.size(), "\n39990000000,nan\n");
  {
    std::fstream f(dir.path() / "gyro.csv", std::ios::in | std::ios::out | std::ios::binary);
    f << gyro;  // the same inode, as an editor writing in place would
  }
  hal::SensorEvent ev;
  int gyro_events = 0;
  while (src->read(ev)) {
    gyro_events += ev.kind == hal::SensorEvent::Kind::kGyro ? 1 : 0;
  }
  EXPECT_EQ(gyro_events, 3999);
  EXPECT_TRUE(src->exhausted());
  EXPECT_TRUE(contains(src->stream_error(),
                       "gyro.csv:4001: wz_rad_s: expected a finite number, got \"nan\""))
      << src->stream_error();
  EXPECT_EQ(load_error(dir.str()), src->stream_error());
}
