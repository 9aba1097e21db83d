// Real-kernel check of the V4L2 driver on vivid: negotiation (GREY, YUYV luma, 640x480 reduced
// to 320x240), memory-mapped streaming at the configured rate with monotonic driver time stamps,
// a refused format explained, a missing device, and a device that vanishes and comes back.
#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cleanslam/drivers/diagnostics.hpp"
#include "cleanslam/drivers/v4l2_camera.hpp"
#include "kernel_check.hpp"

namespace {

using cleanslam::hal::SensorEvent;
using cleanslam::hal::TimeNs;
using cleanslam::kernel_test::Check;
namespace drivers = cleanslam::drivers;

TimeNs now_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<TimeNs>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

class Collected : public drivers::Diagnostics {
 public:
  std::string text;
  void report(drivers::Severity, std::string_view component, std::string_view message) override {
    text += std::string(message) + "\n";
    std::printf("    diagnostics %.*s: %.*s\n", static_cast<int>(component.size()),
                component.data(), static_cast<int>(message.size()), message.data());
    std::fflush(stdout);
  }
  [[nodiscard]] bool has(const std::string& s) const { return text.find(s) != std::string::npos; }
};

struct Shot {
  TimeNs t_ns = 0;
  TimeNs received_ns = 0;
  std::vector<std::uint8_t> pixels;
};

std::vector<Shot> stream(drivers::V4l2Camera& camera, TimeNs duration_ns) {
  std::vector<Shot> shots;
  const TimeNs end = now_ns() + duration_ns;
  while (now_ns() < end) {
    pollfd p{camera.fd(), POLLIN, 0};
    ::poll(&p, 1, 50);
    SensorEvent e;
    while (camera.read(e)) {
      const auto& im = e.frame.image;
      Shot s;
      s.t_ns = e.frame.t_ns;
      s.received_ns = now_ns();
      for (int y = 0; y < im.height; ++y) {
        s.pixels.insert(s.pixels.end(), im.row(y), im.row(y) + im.width);
      }
      shots.push_back(std::move(s));
    }
  }
  return shots;
}

double spread(const std::vector<std::uint8_t>& p) {
  double mean = 0.0;
  for (auto v : p) {
    mean += v;
  }
  mean /= static_cast<double>(p.size());
  double var = 0.0;
  for (auto v : p) {
    var += (v - mean) * (v - mean);
  }
  return std::sqrt(var / static_cast<double>(p.size()));
}

std::vector<std::uint8_t> first_grey;

// vivid stamps the nominal end of a frame, which lies after its dequeue; its "Timestamp Source"
// control set to "Start of Exposure" gives stamps in the past, which the driver passes through.
bool set_vivid_start_of_exposure() {
  const int fd = ::open("/dev/video0", O_RDWR);
  bool ok = false;
  v4l2_queryctrl q{};
  q.id = V4L2_CTRL_FLAG_NEXT_CTRL;
  while (fd >= 0 && ::ioctl(fd, VIDIOC_QUERYCTRL, &q) == 0) {
    if (std::string(reinterpret_cast<const char*>(q.name)) == "Timestamp Source") {
      v4l2_control c{q.id, 1};
      ok = ::ioctl(fd, VIDIOC_S_CTRL, &c) == 0;
      break;
    }
    q.id |= V4L2_CTRL_FLAG_NEXT_CTRL;
  }
  if (fd >= 0) {
    ::close(fd);
  }
  return ok;
}

bool check_stream() {
  Check check("camera_stream");
  drivers::V4l2CameraConfig config;
  config.rate_hz = 2.0;
  config.device_fps = 10.0;
  check.expect(set_vivid_start_of_exposure(),
               "cannot set vivid's time stamps to start of exposure");
  drivers::V4l2Camera camera(config);
  if (!check.expect(camera.streaming(), "not streaming")) {
    return check.finish() == 0;
  }
  const auto& f = camera.format();
  check.note("format %s %dx%d scale %d at %.3g fps", drivers::fourcc_name(f.fourcc).c_str(),
             f.width, f.height, f.scale, f.fps);
  check.expect(drivers::fourcc_name(f.fourcc) == "GREY", "format %s, GREY preferred",
               drivers::fourcc_name(f.fourcc).c_str());
  const auto shots = stream(camera, 3'300'000'000);
  const auto& s = camera.stats();
  check.note(
      "%zu frames delivered of %llu dequeued (%llu dropped for the rate, %llu stamps "
      "past their dequeue)",
      shots.size(), static_cast<unsigned long long>(s.dequeued),
      static_cast<unsigned long long>(s.dropped_rate),
      static_cast<unsigned long long>(s.future_stamps));
  check.expect(shots.size() >= 6 && shots.size() <= 8, "%zu frames in 3.3 s at 2 Hz", shots.size());
  check.expect(s.dropped_rate >= shots.size(), "frames beyond the rate were not dropped");
  bool stamps_ok = true;
  for (std::size_t i = 0; i < shots.size(); ++i) {
    stamps_ok = stamps_ok && shots[i].t_ns <= shots[i].received_ns &&
                shots[i].received_ns - shots[i].t_ns < 500'000'000 &&
                (i == 0 || shots[i].t_ns > shots[i - 1].t_ns);
  }
  if (!stamps_ok && shots.size() >= 2) {
    check.note("first stamp %.3f s received %.3f s; second %.3f s received %.3f s",
               static_cast<double>(shots[0].t_ns) * 1e-9,
               static_cast<double>(shots[0].received_ns) * 1e-9,
               static_cast<double>(shots[1].t_ns) * 1e-9,
               static_cast<double>(shots[1].received_ns) * 1e-9);
  }
  check.expect(stamps_ok, "driver time stamps not monotonic or not close to reception");
  // With start-of-exposure stamps every driver stamp precedes its dequeue and is used as is.
  std::string steps;
  for (std::size_t i = 1; i < shots.size(); ++i) {
    steps += std::to_string((shots[i].t_ns - shots[i - 1].t_ns) / 100'000) + " ";
  }
  check.note("stamp steps (0.1 ms): %s", steps.c_str());
  check.expect(s.future_stamps == 0, "%llu driver stamps lay after their dequeue",
               static_cast<unsigned long long>(s.future_stamps));
  if (shots.size() >= 3) {
    const double mean_interval = static_cast<double>(shots.back().t_ns - shots.front().t_ns) *
                                 1e-9 / static_cast<double>(shots.size() - 1);
    check.note("mean interval %.3f s", mean_interval);
    check.expect(std::fabs(mean_interval - 0.5) < 0.075, "mean interval %.3f s, expected 0.5",
                 mean_interval);
  }
  if (!shots.empty()) {
    check.expect(shots[0].pixels.size() == 320U * 240U, "image of %zu pixels",
                 shots[0].pixels.size());
    check.expect(spread(shots[0].pixels) > 20.0, "image nearly uniform (std %.1f)",
                 spread(shots[0].pixels));
    first_grey = shots[0].pixels;
  }
  return check.finish() == 0;
}

bool check_yuyv() {
  Check check("camera_yuyv");
  drivers::V4l2CameraConfig config;
  config.pixel_format = "YUYV";
  config.rate_hz = 2.0;
  drivers::V4l2Camera camera(config);
  if (!check.expect(camera.streaming(), "not streaming YUYV")) {
    return check.finish() == 0;
  }
  const auto shots = stream(camera, 1'200'000'000);
  check.expect(shots.size() >= 2, "%zu YUYV frames", shots.size());
  if (!shots.empty() && first_grey.size() == shots[0].pixels.size()) {
    // vivid's GREY is full range and its YUYV luma limited range: compare by correlation.
    const auto& a = first_grey;
    const auto& b = shots[0].pixels;
    double ma = 0.0, mb = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      ma += a[i];
      mb += b[i];
    }
    ma /= static_cast<double>(a.size());
    mb /= static_cast<double>(b.size());
    double sab = 0.0, saa = 0.0, sbb = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      sab += (a[i] - ma) * (b[i] - mb);
      saa += (a[i] - ma) * (a[i] - ma);
      sbb += (b[i] - mb) * (b[i] - mb);
    }
    const double ncc = sab / std::sqrt(saa * sbb + 1e-12);
    check.note("GREY mean %.1f, YUYV luma mean %.1f, correlation %.3f", ma, mb, ncc);
    check.expect(ncc > 0.95, "YUYV luma does not match the GREY image (correlation %.3f)", ncc);
  }
  return check.finish() == 0;
}

bool check_refused() {
  Check check("camera_refused");
  Collected diag;
  drivers::V4l2CameraConfig config;
  config.max_scale = 1;  // vivid's webcam has no 320x240
  drivers::V4l2Camera camera(config, drivers::linux_os(), diag);
  SensorEvent e;
  check.expect(!camera.streaming() && !camera.read(e), "streaming although refused");
  check.expect(diag.has("refuses the format: asked for GREY 320x240") &&
                   diag.has("the device offers 320x180, 640x360, 640x480"),
               "refusal not explained with what the device offers");
  config.device = "/dev/video7";
  drivers::V4l2Camera missing(config, drivers::linux_os(), diag);
  check.expect(!missing.streaming() && !missing.read(e), "missing device streaming");
  check.expect(diag.has("cannot open camera '/dev/video7' (No such file or directory)"),
               "missing device not explained");
  return check.finish() == 0;
}

bool check_vanished() {
  Check check("camera_vanished");
  Collected diag;
  drivers::V4l2CameraConfig config;
  config.rate_hz = 5.0;
  config.reopen_min_ns = 100'000'000;
  drivers::V4l2Camera camera(config, drivers::linux_os(), diag);
  const int fd_before = camera.fd();
  auto shots = stream(camera, 600'000'000);
  check.expect(!shots.empty(), "no frames before the device vanished");
  // Unbinding the platform device unregisters /dev/video0 under the open descriptor.
  check.expect(std::system("echo vivid.0 > /sys/bus/platform/drivers/vivid/unbind") == 0,
               "unbinding vivid failed");
  stream(camera, 500'000'000);
  check.expect(!camera.streaming() && camera.stats().stream_errors >= 1,
               "vanished device not noticed");
  check.expect(std::system("echo vivid.0 > /sys/bus/platform/drivers/vivid/bind") == 0,
               "binding vivid again failed");
  shots = stream(camera, 2'500'000'000);
  check.expect(camera.streaming() && !shots.empty(),
               "not streaming again after the device came "
               "back (%zu frames)",
               shots.size());
  check.expect(camera.fd() == fd_before, "fd() changed across the reopen");
  check.note("stream errors %llu, opens %llu, %zu frames after the return",
             static_cast<unsigned long long>(camera.stats().stream_errors),
             static_cast<unsigned long long>(camera.stats().opens), shots.size());
  return check.finish() == 0;
}

}  // namespace

int main() {
  bool ok = check_stream();
  ok = check_yuyv() && ok;
  ok = check_refused() && ok;
  ok = check_vanished() && ok;
  return ok ? 0 : 1;
}
