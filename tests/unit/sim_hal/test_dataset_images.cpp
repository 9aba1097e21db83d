#include <gtest/gtest.h>
#include <png.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/sim_hal/dataset_writer.hpp"
#include "sim_test_files.hpp"
#include "text_checks.hpp"

// The images of a dataset: what is refused besides a missing or malformed one.
namespace {

namespace fs = std::filesystem;
using cleanslam::sim_hal::DatasetWriter;
using cleanslam::sim_test::load_error;
using cleanslam::sim_test::TempDir;
using cleanslam::test::contains;

// A 32x24 dataset with two PNG images, 250000000.png and 750000000.png.
void make_images_dataset(const std::string& folder) {
  cleanslam::hal::Calibration cal;
  cal.camera.width = 32;
  cal.camera.height = 24;
  cal.camera.fx = cal.camera.fy = 28.0;
  cal.camera.cx = 15.5;
  cal.camera.cy = 11.5;
  DatasetWriter w;
  ASSERT_TRUE(w.open(folder, cal, DatasetWriter::ImageFormat::kPng).ok());
  for (int i = 0; i < 100; ++i) {
    w.add_gyro(cleanslam::hal::GyroSample{i * 10'000'000LL, 0.0, 0, 0, false, 0});
  }
  for (int i = 0; i < 20; ++i) {
    w.add_encoder(cleanslam::hal::EncoderSample{i * 50'000'000LL + 1, 0, 0, 0});
  }
  const std::vector<std::uint8_t> grey(32 * 24, 0x80);
  const cleanslam::hal::GrayImageView view{grey.data(), 32, 24, 32};
  ASSERT_TRUE(w.add_image(250'000'000, view).ok());
  ASSERT_TRUE(w.add_image(750'000'000, view).ok());
  ASSERT_TRUE(w.close().ok());
}

TEST(DatasetImages, ALinkOutOfTheFolderIsRefused) {
  TempDir dir;
  make_images_dataset(dir.sub("ds"));
  const fs::path image = fs::path(dir.sub("ds")) / "cam0" / "data" / "250000000.png";
  fs::copy_file(image, dir.sub("outside.png"));
  fs::remove(image);
  fs::create_symlink(dir.sub("outside.png"), image);
  const std::string e = load_error(dir.sub("ds"));
  EXPECT_TRUE(contains(e, "cam0/data.csv:2: filename:") &&
              contains(e, "outside the dataset folder") && contains(e, "a symbolic link out of it"))
      << e;
  // A link that stays inside the folder is read.
  fs::remove(image);
  fs::create_symlink("750000000.png", image);
  EXPECT_EQ(load_error(dir.sub("ds")), "");
}

TEST(DatasetImages, AFifoIsNotARegularFileRatherThanMissing) {
  TempDir dir;
  make_images_dataset(dir.sub("ds"));
  const fs::path image = fs::path(dir.sub("ds")) / "cam0" / "data" / "750000000.png";
  fs::remove(image);
  ASSERT_EQ(::mkfifo(image.c_str(), 0600), 0);
  const std::string e = load_error(dir.sub("ds"));
  EXPECT_TRUE(contains(e, "cam0/data.csv:3: filename:") &&
              contains(e, "750000000.png: is a FIFO, not a regular file"))
      << e;
}

TEST(DatasetImages, AGreyAndAlphaPngIsRefused) {
  TempDir dir;
  make_images_dataset(dir.sub("ds"));
  const fs::path image = fs::path(dir.sub("ds")) / "cam0" / "data" / "250000000.png";
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = 32;
  png.height = 24;
  png.format = PNG_FORMAT_GA;
  const std::vector<std::uint8_t> ga(32 * 24 * 2, 0x80);
  ASSERT_NE(png_image_write_to_file(&png, image.c_str(), 0, ga.data(), 0, nullptr), 0);
  const std::string e = load_error(dir.sub("ds"));
  EXPECT_TRUE(contains(e, "250000000.png: PNG has an alpha channel")) << e;
}

}  // namespace
