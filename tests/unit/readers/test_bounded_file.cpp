#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cleanslam/readers/bounded_file.hpp"
#include "cleanslam/readers/yaml_document.hpp"

namespace fs = std::filesystem;
namespace r = cleanslam::readers;

namespace {

class BoundedFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cleanslam_bounded_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  [[nodiscard]] std::string path(const char* name) const { return (dir_ / name).string(); }
  [[nodiscard]] std::string write(const char* name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }

  fs::path dir_;
};

constexpr r::FileLimit kTen{10, "test::kTen", "a test file"};

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST_F(BoundedFile, ReadsARegularFileWithinItsLimit) {
  const auto text = r::read_bounded_file(write("ok.txt", "0123456789"), kTen);
  ASSERT_TRUE(text.ok()) << text.error();
  EXPECT_EQ(*text, "0123456789");
  const auto bytes = r::read_bounded_bytes(path("ok.txt"), kTen);
  ASSERT_TRUE(bytes.ok()) << bytes.error();
  EXPECT_EQ(bytes->size(), 10U);
  EXPECT_TRUE(r::check_bounded_file(path("ok.txt"), kTen).ok());
}

TEST_F(BoundedFile, ALargerFileIsRefusedNamingTheLimit) {
  const std::string p = write("big.txt", "01234567890");
  const auto text = r::read_bounded_file(p, kTen);
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error(),
            p + ": 11 bytes, more than the 10 bytes test::kTen allows for a test file");
  EXPECT_EQ(r::check_bounded_file(p, kTen).error(), text.error());
}

TEST_F(BoundedFile, ADirectoryIsRefused) {
  const auto text = r::read_bounded_file(dir_.string(), kTen);
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error(), dir_.string() + ": is a directory, not a regular file");
}

TEST_F(BoundedFile, AFifoIsRefusedWithoutBlocking) {
  ASSERT_EQ(::mkfifo(path("f").c_str(), 0600), 0);
  const auto text = r::read_bounded_file(path("f"), kTen);
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error(), path("f") + ": is a FIFO, not a regular file");
  // Through a symbolic link too.
  fs::create_symlink(path("f"), path("link"));
  EXPECT_TRUE(contains(r::check_bounded_file(path("link"), kTen).error(), "is a FIFO"));
}

TEST_F(BoundedFile, ADeviceThatNeverEndsIsRefused) {
  const auto text = r::read_bounded_bytes("/dev/zero", r::kLogFileLimit);
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error(), "/dev/zero: is a character device, not a regular file");
}

TEST_F(BoundedFile, AMissingFileSaysWhy) {
  const auto text = r::read_bounded_file(path("none"), kTen);
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error(), path("none") + ": cannot open: No such file or directory");
}

TEST_F(BoundedFile, AYamlFileBeyondItsLimitIsRefused) {
  const std::string p = write(
      "big.yaml", std::string(static_cast<std::size_t>(r::kYamlFileLimit.max_bytes), '#') + "\n");
  const auto doc = r::yaml::parse_file(p);
  ASSERT_FALSE(doc.ok());
  EXPECT_TRUE(contains(doc.error(), "more than the 1048576 bytes readers::kYamlFileLimit allows"))
      << doc.error();
}

TEST(YamlDocuments, ASecondDocumentIsRefused) {
  const auto doc = r::yaml::parse_string("a: 1\n---\nb: 2\n", "two.yaml");
  ASSERT_FALSE(doc.ok());
  EXPECT_TRUE(contains(doc.error(), "two.yaml:2: a second YAML document")) << doc.error();
  // An explicit start and end of one document are fine.
  const auto one = r::yaml::parse_string("---\na: 1\n...\n", "one.yaml");
  ASSERT_TRUE(one.ok()) << one.error();
  EXPECT_NE(one->find("a"), nullptr);
}

}  // namespace
