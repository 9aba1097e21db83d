#include <linux/videodev2.h>

#include <gtest/gtest.h>

#include "cleanslam/drivers/luma.hpp"
#include "cleanslam/drivers/v4l2_camera.hpp"
#include "fake_v4l2.hpp"

namespace cleanslam::drivers {
namespace {

using testing::FakeV4l2;
using testing::kMs;
using testing::RecordingDiagnostics;

int pattern(int x, int y) {
  return (x * 3 + y * 7) % 251;
}

class V4l2CameraTest : public ::testing::Test {
 protected:
  FakeV4l2 os;
  RecordingDiagnostics diag;
  V4l2CameraConfig config;
};

TEST_F(V4l2CameraTest, NegotiatesGrey320x240AndStreamsFromMappedBuffers) {
  V4l2Camera camera(config, os, diag);
  ASSERT_TRUE(camera.streaming()) << diag.all();
  EXPECT_EQ(os.format.pixelformat, V4L2_PIX_FMT_GREY);
  EXPECT_EQ(os.format.width, 320U);
  EXPECT_EQ(camera.format().scale, 1);
  EXPECT_EQ(os.buffers.size(), 4U);
  EXPECT_EQ(os.queued.size(), 4U);
  EXPECT_EQ(os.mapped, 4);
  EXPECT_DOUBLE_EQ(camera.format().fps, 10.0);
  hal::SensorEvent e;
  EXPECT_FALSE(camera.read(e));
  os.produce(os.mono_ns - 5 * kMs, pattern);
  ASSERT_TRUE(camera.read(e));
  EXPECT_EQ(e.kind, hal::SensorEvent::Kind::kFrame);
  EXPECT_EQ(e.frame.t_ns, os.mono_ns - 5 * kMs);
  ASSERT_TRUE(e.frame.has_image());
  EXPECT_EQ(e.frame.image.width, 320);
  EXPECT_EQ(e.frame.image.height, 240);
  EXPECT_EQ(e.frame.image.at(10, 20), pattern(10, 20));
  EXPECT_EQ(e.frame.image.at(319, 239), pattern(319, 239));
  EXPECT_EQ(os.queued.size(), 4U);  // the buffer went straight back
}

TEST_F(V4l2CameraTest, YuyvIsReducedToItsLuma) {
  os.formats = {V4L2_PIX_FMT_YUYV};
  V4l2Camera camera(config, os, diag);
  ASSERT_TRUE(camera.streaming()) << diag.all();
  EXPECT_EQ(os.format.pixelformat, V4L2_PIX_FMT_YUYV);
  os.produce(os.mono_ns, pattern);
  hal::SensorEvent e;
  ASSERT_TRUE(camera.read(e));
  EXPECT_EQ(e.frame.image.at(7, 9), pattern(7, 9));
  EXPECT_EQ(e.frame.image.at(300, 200), pattern(300, 200));
}

TEST_F(V4l2CameraTest, LargerMultipleIsBoxAveragedTo320x240) {
  os.sizes = {{320, 180}, {640, 480}};
  V4l2Camera camera(config, os, diag);
  ASSERT_TRUE(camera.streaming()) << diag.all();
  EXPECT_EQ(os.format.width, 640U);
  EXPECT_EQ(camera.format().scale, 2);
  os.produce(os.mono_ns, [](int x, int y) { return (x % 2) * 100 + (y % 2) * 20; });
  hal::SensorEvent e;
  ASSERT_TRUE(camera.read(e));
  EXPECT_EQ(e.frame.image.at(5, 5), 60);  // (0 + 100 + 20 + 120) / 4
}

TEST_F(V4l2CameraTest, RefusedPixelFormatIsExplained) {
  os.formats = {v4l2_fourcc('M', 'J', 'P', 'G'), v4l2_fourcc('R', 'G', 'B', '3')};
  V4l2Camera camera(config, os, diag);
  EXPECT_FALSE(camera.streaming());
  EXPECT_GE(camera.fd(), 0);
  hal::SensorEvent e;
  EXPECT_FALSE(camera.read(e));
  EXPECT_TRUE(
      diag.any_contains("refuses the format: asked for GREY or YUYV, the device offers: "
                        "MJPG, RGB3"))
      << diag.all();
  EXPECT_EQ(os.device_fd, -1);
}

TEST_F(V4l2CameraTest, RefusedSizeIsExplained) {
  os.sizes = {{320, 180}, {1280, 720}};
  V4l2Camera camera(config, os, diag);
  EXPECT_FALSE(camera.streaming());
  EXPECT_TRUE(
      diag.any_contains("asked for GREY 320x240 or an integer multiple up to x4, the "
                        "device offers 320x180, 1280x720"))
      << diag.all();
}

TEST_F(V4l2CameraTest, NotACaptureDeviceIsExplained) {
  os.capabilities = V4L2_CAP_VIDEO_OUTPUT | V4L2_CAP_STREAMING;
  V4l2Camera camera(config, os, diag);
  EXPECT_FALSE(camera.streaming());
  EXPECT_TRUE(
      diag.any_contains("card 'Fake Camera', driver 'fake') is not a single-planar "
                        "streaming capture device"))
      << diag.all();
}

TEST_F(V4l2CameraTest, TooFewBuffersIsExplained) {
  os.max_buffers = 1;
  V4l2Camera camera(config, os, diag);
  EXPECT_FALSE(camera.streaming());
  EXPECT_TRUE(diag.any_contains("at least 2 needed")) << diag.all();
  EXPECT_EQ(os.mapped, 0);
}

TEST_F(V4l2CameraTest, FramesBeyondTheRateAreDroppedAndRequeued) {
  config.rate_hz = 2.0;
  V4l2Camera camera(config, os, diag);
  hal::SensorEvent e;
  std::vector<hal::TimeNs> delivered;
  const hal::TimeNs t0 = os.mono_ns;
  for (int i = 0; i < 30; ++i) {  // 3 s at 10 fps
    os.mono_ns = t0 + i * 100 * kMs;
    ASSERT_TRUE(os.produce(os.mono_ns, pattern));
    while (camera.read(e)) {
      delivered.push_back(e.frame.t_ns - t0);
    }
  }
  EXPECT_EQ(delivered, (std::vector<hal::TimeNs>{0, 500 * kMs, 1000 * kMs, 1500 * kMs, 2000 * kMs,
                                                 2500 * kMs}));
  EXPECT_EQ(camera.stats().dropped_rate, 24U);
  EXPECT_EQ(os.queued.size(), 4U);
}

TEST_F(V4l2CameraTest, SlowDeviceFramesAllPassAndTheGridFollowsThem) {
  config.rate_hz = 2.0;
  V4l2Camera camera(config, os, diag);
  hal::SensorEvent e;
  const hal::TimeNs t0 = os.mono_ns;
  int n = 0;
  for (int i = 0; i < 5; ++i) {  // 1.5 fps
    os.mono_ns = t0 + i * 667 * kMs;
    os.produce(os.mono_ns, pattern);
    n += camera.read(e) ? 1 : 0;
  }
  EXPECT_EQ(n, 5);
}

TEST_F(V4l2CameraTest, CorruptAndShortBuffersAreDropped) {
  V4l2Camera camera(config, os, diag);
  hal::SensorEvent e;
  os.produce(os.mono_ns, pattern, V4L2_BUF_FLAG_ERROR);
  EXPECT_FALSE(camera.read(e));
  os.produce(os.mono_ns, pattern);
  os.ready.back().bytesused = 100;
  EXPECT_FALSE(camera.read(e));
  EXPECT_EQ(camera.stats().dropped_error, 2U);
  EXPECT_EQ(os.queued.size(), 4U);
}

TEST_F(V4l2CameraTest, DeviceSequenceGapsAreCounted) {
  V4l2Camera camera(config, os, diag);
  hal::SensorEvent e;
  os.produce(os.mono_ns, pattern);
  camera.read(e);
  os.next_sequence += 3;
  os.mono_ns += hal::kNsPerSecond;
  os.produce(os.mono_ns, pattern);
  camera.read(e);
  EXPECT_EQ(camera.stats().device_dropped, 3U);
}

TEST_F(V4l2CameraTest, WithoutMonotonicStampsTheDequeueTimeIsUsed) {
  os.timestamp_flags = V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN;
  V4l2Camera camera(config, os, diag);
  hal::SensorEvent e;
  os.produce(12345, pattern);
  ASSERT_TRUE(camera.read(e));
  EXPECT_EQ(e.frame.t_ns, os.mono_ns);
  EXPECT_TRUE(diag.any_contains("no monotonic time stamps")) << diag.all();
}

TEST_F(V4l2CameraTest, StampsAfterTheDequeueAreClamped) {
  V4l2Camera camera(config, os, diag);
  hal::SensorEvent e;
  os.produce(os.mono_ns + 80 * kMs, pattern);
  ASSERT_TRUE(camera.read(e));
  EXPECT_EQ(e.frame.t_ns, os.mono_ns);
  EXPECT_EQ(camera.stats().future_stamps, 1U);
}

TEST_F(V4l2CameraTest, EioClosesAndReopensWithBackoff) {
  V4l2Camera camera(config, os, diag);
  const int fd = camera.fd();
  hal::SensorEvent e;
  os.dqbuf_error = EIO;
  EXPECT_FALSE(camera.read(e));
  EXPECT_FALSE(camera.streaming());
  EXPECT_EQ(os.mapped, 0);
  EXPECT_TRUE(diag.any_contains("stream error (Input/output error); closing, reopening in 0.25 s"))
      << diag.all();
  os.dqbuf_error = 0;
  os.mono_ns += 100 * kMs;
  EXPECT_FALSE(camera.read(e));
  EXPECT_FALSE(camera.streaming());
  os.mono_ns += 200 * kMs;
  EXPECT_FALSE(camera.read(e));
  EXPECT_TRUE(camera.streaming());
  EXPECT_EQ(camera.fd(), fd);
  os.produce(os.mono_ns, pattern);
  EXPECT_TRUE(camera.read(e));
  EXPECT_EQ(camera.stats().opens, 2U);
}

TEST_F(V4l2CameraTest, MissingDeviceIsExplainedAndPickedUpWhenItAppears) {
  os.present = false;
  V4l2Camera camera(config, os, diag);
  EXPECT_FALSE(camera.streaming());
  EXPECT_TRUE(diag.any_contains("cannot open camera '/dev/video0' (No such file or directory)"))
      << diag.all();
  hal::SensorEvent e;
  os.mono_ns += hal::kNsPerSecond;
  EXPECT_FALSE(camera.read(e));
  os.present = true;
  os.mono_ns += 10 * hal::kNsPerSecond;
  EXPECT_FALSE(camera.read(e));
  EXPECT_TRUE(camera.streaming());
}

TEST(Luma, GreyYuyvAndBoxReduction) {
  const std::uint8_t grey[] = {1, 2, 3, 4, 99,  //
                               5, 6, 7, 8, 99};
  std::uint8_t out[8] = {};
  extract_luma(grey, 4, 2, 5, PixelLayout::kGrey, 1, out);
  EXPECT_EQ(out[0], 1);
  EXPECT_EQ(out[3], 4);
  EXPECT_EQ(out[4], 5);  // second row after the stride's padding
  extract_luma(grey, 4, 2, 5, PixelLayout::kGrey, 2, out);
  EXPECT_EQ(out[0], 4);  // (1+2+5+6)/4 = 3.5 rounds to 4
  EXPECT_EQ(out[1], 6);  // (3+4+7+8)/4 = 5.5 rounds to 6
  const std::uint8_t yuyv[] = {10, 128, 20, 128, 30, 128, 40, 128};
  extract_luma(yuyv, 4, 1, 8, PixelLayout::kYuyv, 1, out);
  EXPECT_EQ(out[0], 10);
  EXPECT_EQ(out[1], 20);
  EXPECT_EQ(out[3], 40);
}

}  // namespace
}  // namespace cleanslam::drivers

namespace cleanslam::drivers {
namespace {

TEST(V4l2CameraConfig, OutOfRangeRateIsReplacedAndSaid) {
  testing::FakeV4l2 os;
  testing::RecordingDiagnostics diag;
  V4l2CameraConfig config;
  config.rate_hz = 0.0;
  V4l2Camera camera(config, os, diag);
  EXPECT_TRUE(camera.streaming());
  EXPECT_TRUE(diag.any_contains("rate_hz = 0 is outside (0, 60]: using 2 Hz")) << diag.all();
}

}  // namespace
}  // namespace cleanslam::drivers
