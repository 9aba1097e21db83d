#include "cleanslam/drivers/v4l2_camera.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <utility>

namespace cleanslam::drivers {
namespace {

constexpr std::string_view kCameraComponent = "camera";
constexpr int kWidth = hal::kImageWidth;
constexpr int kHeight = hal::kImageHeight;

struct Size {
  int width = 0;
  int height = 0;
};

// A size the driver can use: 320x240 times an integer factor up to max_scale.
int scale_of(Size s, int max_scale) {
  if (s.width % kWidth != 0 || s.height % kHeight != 0) {
    return 0;
  }
  const int k = s.width / kWidth;
  return k >= 1 && k <= max_scale && s.height == kHeight * k ? k : 0;
}

}  // namespace

std::string fourcc_name(std::uint32_t fourcc) {
  std::string s(4, ' ');
  for (std::size_t i = 0; i < 4; ++i) {
    const auto c = static_cast<char>((fourcc >> (8 * i)) & 0xFFU);
    s[i] = c >= 32 && c < 127 ? c : '?';
  }
  return s;
}

V4l2Camera::V4l2Camera(V4l2CameraConfig config, Os& os, Diagnostics& diagnostics)
    : config_(std::move(config)),
      os_(os),
      diagnostics_(diagnostics),
      readiness_(os),
      backoff_(config_.reopen_min_ns, config_.reopen_max_ns),
      image_(static_cast<std::size_t>(kWidth * kHeight)) {
  if (!(config_.rate_hz > 0.0 && config_.rate_hz <= 60.0)) {
    reportf(diagnostics_, Severity::kWarning, kCameraComponent,
            "rate_hz = %g is outside (0, 60]: using 2 Hz", config_.rate_hz);
    config_.rate_hz = 2.0;
  }
  if (!(config_.device_fps > 0.0 && config_.device_fps <= 240.0)) {
    reportf(diagnostics_, Severity::kWarning, kCameraComponent,
            "device_fps = %g is outside (0, 240]: using 5", config_.device_fps);
    config_.device_fps = 5.0;
  }
  if (config_.max_scale < 1) {
    config_.max_scale = 1;
  }
  if (config_.buffers < 2) {
    reportf(diagnostics_, Severity::kWarning, kCameraComponent,
            "buffers = %d is too few for streaming: using 2", config_.buffers);
    config_.buffers = 2;
  }
  if (!open_device()) {
    readiness_.arm_timer(backoff_.next());
  }
}

V4l2Camera::~V4l2Camera() {
  close_device();
}

void V4l2Camera::close_device() {
  if (fd_ < 0) {
    return;
  }
  if (streaming_) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    os_.ioctl(fd_, VIDIOC_STREAMOFF, &type);
    streaming_ = false;
  }
  for (const Buffer& b : buffers_) {
    os_.munmap(b.data, b.length);
  }
  buffers_.clear();
  readiness_.unwatch(fd_);
  os_.close(fd_);
  fd_ = -1;
}

bool V4l2Camera::open_device() {
  const char* path = config_.device.c_str();
  fd_ = os_.open(path, O_RDWR | O_NONBLOCK);
  if (fd_ < 0) {
    ++stats_.open_failures;
    reportf(diagnostics_, Severity::kError, kCameraComponent,
            "cannot open camera '%s' (%s); running without vision, retrying with back-off", path,
            std::strerror(errno));
    return false;
  }
  if (!negotiate() || !start_streaming()) {
    ++stats_.open_failures;
    close_device();
    return false;
  }
  ++stats_.opens;
  backoff_.reset();
  has_device_seq_ = false;
  readiness_.watch(fd_);
  reportf(diagnostics_, Severity::kInfo, kCameraComponent,
          "'%s' streaming %s %dx%d%s at %.3g fps, %zu buffers, delivering %.3g Hz", path,
          fourcc_name(format_.fourcc).c_str(), format_.width, format_.height,
          format_.scale > 1 ? " (reduced to 320x240)" : "", format_.fps, buffers_.size(),
          config_.rate_hz);
  return true;
}

bool V4l2Camera::negotiate() {
  const char* path = config_.device.c_str();
  v4l2_capability cap{};
  if (os_.ioctl(fd_, VIDIOC_QUERYCAP, &cap) < 0) {
    reportf(diagnostics_, Severity::kError, kCameraComponent,
            "'%s' is not a V4L2 device (VIDIOC_QUERYCAP: %s)", path, std::strerror(errno));
    return false;
  }
  const std::uint32_t caps =
      (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps : cap.capabilities;
  if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0 || (caps & V4L2_CAP_STREAMING) == 0) {
    reportf(diagnostics_, Severity::kError, kCameraComponent,
            "'%s' (card '%s', driver '%s') is not a single-planar streaming capture device "
            "(capabilities 0x%08X; need VIDEO_CAPTURE 0x1 and STREAMING 0x4000000)",
            path, reinterpret_cast<const char*>(cap.card),
            reinterpret_cast<const char*>(cap.driver), static_cast<unsigned>(caps));
    return false;
  }

  // Pixel format: GREY, else YUYV (or the one configured).
  std::string offered;
  bool has_grey = false;
  bool has_yuyv = false;
  for (std::uint32_t i = 0; i < 64; ++i) {
    v4l2_fmtdesc desc{};
    desc.index = i;
    desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (os_.ioctl(fd_, VIDIOC_ENUM_FMT, &desc) < 0) {
      break;
    }
    has_grey = has_grey || desc.pixelformat == V4L2_PIX_FMT_GREY;
    has_yuyv = has_yuyv || desc.pixelformat == V4L2_PIX_FMT_YUYV;
    offered += (offered.empty() ? "" : ", ") + fourcc_name(desc.pixelformat);
  }
  const std::string& want = config_.pixel_format;
  std::uint32_t fourcc = 0;
  if ((want == "auto" || want == "GREY") && has_grey) {
    fourcc = V4L2_PIX_FMT_GREY;
  } else if ((want == "auto" || want == "YUYV") && has_yuyv) {
    fourcc = V4L2_PIX_FMT_YUYV;
  }
  if (fourcc == 0) {
    reportf(diagnostics_, Severity::kError, kCameraComponent,
            "'%s' (card '%s') refuses the format: asked for %s, the device offers: %s", path,
            reinterpret_cast<const char*>(cap.card), want == "auto" ? "GREY or YUYV" : want.c_str(),
            offered.empty() ? "no formats" : offered.c_str());
    return false;
  }

  // Frame size: 320x240, else the smallest integer multiple of it.
  Size best{};
  int best_scale = 0;
  std::string sizes;
  bool enumerated = false;
  for (std::uint32_t i = 0; i < 64; ++i) {
    v4l2_frmsizeenum fs{};
    fs.index = i;
    fs.pixel_format = fourcc;
    if (os_.ioctl(fd_, VIDIOC_ENUM_FRAMESIZES, &fs) < 0) {
      break;
    }
    enumerated = true;
    if (fs.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
      const Size s{static_cast<int>(fs.discrete.width), static_cast<int>(fs.discrete.height)};
      sizes +=
          (sizes.empty() ? "" : ", ") + std::to_string(s.width) + "x" + std::to_string(s.height);
      const int k = scale_of(s, config_.max_scale);
      if (k > 0 && (best_scale == 0 || k < best_scale)) {
        best = s;
        best_scale = k;
      }
    } else {
      const auto& sw = fs.stepwise;
      sizes += (sizes.empty() ? "" : ", ") + std::to_string(sw.min_width) + "x" +
               std::to_string(sw.min_height) + " to " + std::to_string(sw.max_width) + "x" +
               std::to_string(sw.max_height);
      for (int k = 1; k <= config_.max_scale && best_scale == 0; ++k) {
        const auto w = static_cast<std::uint32_t>(kWidth * k);
        const auto h = static_cast<std::uint32_t>(kHeight * k);
        const bool fits = w >= sw.min_width && w <= sw.max_width && h >= sw.min_height &&
                          h <= sw.max_height && (w - sw.min_width) % sw.step_width == 0 &&
                          (h - sw.min_height) % sw.step_height == 0;
        if (fits) {
          best = Size{kWidth * k, kHeight * k};
          best_scale = k;
        }
      }
      break;
    }
  }
  if (!enumerated) {
    best = Size{kWidth, kHeight};  // the driver does not enumerate: ask and see
  }
  if (enumerated && best_scale == 0) {
    reportf(diagnostics_, Severity::kError, kCameraComponent,
            "'%s' refuses the format: asked for %s 320x240 or an integer multiple up to x%d, "
            "the device offers %s",
            path, fourcc_name(fourcc).c_str(), config_.max_scale, sizes.c_str());
    return false;
  }

  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.width = static_cast<std::uint32_t>(best.width);
  fmt.fmt.pix.height = static_cast<std::uint32_t>(best.height);
  fmt.fmt.pix.pixelformat = fourcc;
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  if (os_.ioctl(fd_, VIDIOC_S_FMT, &fmt) < 0) {
    reportf(diagnostics_, Severity::kError, kCameraComponent,
            "'%s' refuses the format: VIDIOC_S_FMT %s %dx%d failed (%s); the device offers %s "
            "in %s",
            path, fourcc_name(fourcc).c_str(), best.width, best.height, std::strerror(errno),
            offered.c_str(), sizes.empty() ? "unlisted sizes" : sizes.c_str());
    return false;
  }
  const Size got{static_cast<int>(fmt.fmt.pix.width), static_cast<int>(fmt.fmt.pix.height)};
  const int scale = scale_of(got, config_.max_scale);
  const int bytes_per_pixel = fourcc == V4L2_PIX_FMT_YUYV ? 2 : 1;
  if (fmt.fmt.pix.pixelformat != fourcc || scale == 0 ||
      (fmt.fmt.pix.field != V4L2_FIELD_NONE && fmt.fmt.pix.field != V4L2_FIELD_ANY) ||
      static_cast<int>(fmt.fmt.pix.bytesperline) < got.width * bytes_per_pixel) {
    reportf(diagnostics_, Severity::kError, kCameraComponent,
            "'%s' refuses the format: asked for %s %dx%d progressive, the device set %s %dx%d "
            "(field %u, %u bytes per line); it offers %s in %s",
            path, fourcc_name(fourcc).c_str(), best.width, best.height,
            fourcc_name(fmt.fmt.pix.pixelformat).c_str(), got.width, got.height,
            static_cast<unsigned>(fmt.fmt.pix.field),
            static_cast<unsigned>(fmt.fmt.pix.bytesperline), offered.c_str(),
            sizes.empty() ? "unlisted sizes" : sizes.c_str());
    return false;
  }
  format_ = V4l2Format{fourcc, got.width, got.height, static_cast<int>(fmt.fmt.pix.bytesperline),
                       scale,  0.0};

  // Frame interval: ask for device_fps; a device that cannot set it streams at its own rate.
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  parm.parm.capture.timeperframe.numerator = 1000;
  parm.parm.capture.timeperframe.denominator =
      static_cast<std::uint32_t>(std::lround(config_.device_fps * 1000.0));
  if (os_.ioctl(fd_, VIDIOC_S_PARM, &parm) == 0 && parm.parm.capture.timeperframe.numerator > 0) {
    format_.fps = static_cast<double>(parm.parm.capture.timeperframe.denominator) /
                  static_cast<double>(parm.parm.capture.timeperframe.numerator);
    if (format_.fps + 1e-6 < config_.rate_hz) {
      reportf(diagnostics_, Severity::kWarning, kCameraComponent,
              "'%s' streams at %.3g fps (asked %.3g), below the configured %.3g Hz", path,
              format_.fps, config_.device_fps, config_.rate_hz);
    }
  } else {
    reportf(diagnostics_, Severity::kInfo, kCameraComponent,
            "'%s' does not set its frame interval (%s): frames beyond %.3g Hz are dropped", path,
            std::strerror(errno), config_.rate_hz);
  }
  return true;
}

bool V4l2Camera::start_streaming() {
  const char* path = config_.device.c_str();
  v4l2_requestbuffers req{};
  req.count = static_cast<std::uint32_t>(config_.buffers);
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (os_.ioctl(fd_, VIDIOC_REQBUFS, &req) < 0 || req.count < 2) {
    reportf(diagnostics_, Severity::kError, kCameraComponent,
            "'%s' gives no memory-mapped streaming with %d buffers (VIDIOC_REQBUFS: %s, %u "
            "granted; at least 2 needed)",
            path, config_.buffers, std::strerror(errno), static_cast<unsigned>(req.count));
    return false;
  }
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (os_.ioctl(fd_, VIDIOC_QUERYBUF, &buf) < 0) {
      reportf(diagnostics_, Severity::kError, kCameraComponent,
              "'%s': VIDIOC_QUERYBUF %u failed (%s)", path, i, std::strerror(errno));
      return false;
    }
    void* data = os_.mmap(buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_,
                          static_cast<off_t>(buf.m.offset));
    if (data == MAP_FAILED) {
      reportf(diagnostics_, Severity::kError, kCameraComponent,
              "'%s': mmap of buffer %u failed (%s)", path, i, std::strerror(errno));
      return false;
    }
    buffers_.push_back(Buffer{data, buf.length});
    if (os_.ioctl(fd_, VIDIOC_QBUF, &buf) < 0) {
      reportf(diagnostics_, Severity::kError, kCameraComponent, "'%s': VIDIOC_QBUF %u failed (%s)",
              path, i, std::strerror(errno));
      return false;
    }
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (os_.ioctl(fd_, VIDIOC_STREAMON, &type) < 0) {
    reportf(diagnostics_, Severity::kError, kCameraComponent, "'%s': VIDIOC_STREAMON failed (%s)",
            path, std::strerror(errno));
    return false;
  }
  streaming_ = true;
  return true;
}

void V4l2Camera::fail_and_reopen(const char* what, int error) {
  ++stats_.stream_errors;
  const hal::TimeNs delay = backoff_.next();
  reportf(diagnostics_, Severity::kError, kCameraComponent,
          "'%s': %s (%s); closing, reopening in %.2f s", config_.device.c_str(), what,
          std::strerror(error), hal::to_seconds(delay));
  close_device();
  readiness_.arm_timer(delay);
}

// Keeps frames on a grid of 1/rate_hz, so the delivered rate is the configured one on average.
bool V4l2Camera::accept_frame(hal::TimeNs t_ns) {
  const auto period = static_cast<hal::TimeNs>(1e9 / config_.rate_hz);
  if (!has_delivered_ || t_ns >= next_due_ns_ + period) {
    has_delivered_ = true;
    next_due_ns_ = t_ns + period;
    return true;
  }
  if (t_ns >= next_due_ns_) {
    next_due_ns_ += period;
    return true;
  }
  return false;
}

bool V4l2Camera::read(hal::SensorEvent& out) {
  if (fd_ < 0) {
    if (readiness_.timer_fired() && !open_device()) {
      readiness_.arm_timer(backoff_.next());
    }
    if (fd_ < 0) {
      return false;
    }
  }
  for (std::size_t attempt = 0; attempt < buffers_.size(); ++attempt) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    if (os_.ioctl(fd_, VIDIOC_DQBUF, &buf) < 0) {
      const int error = errno;
      if (error == EAGAIN || error == EINTR) {
        return false;
      }
      fail_and_reopen(error == EIO ? "stream error" : "the device went away", error);
      return false;
    }
    ++stats_.dequeued;
    const hal::TimeNs now = os_.monotonic_now();
    hal::TimeNs t_ns = now;
    if ((buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC) {
      t_ns = static_cast<hal::TimeNs>(buf.timestamp.tv_sec) * hal::kNsPerSecond +
             static_cast<hal::TimeNs>(buf.timestamp.tv_usec) * 1000;
      // Some drivers (vivid) stamp the frame's scheduled end, which can lie past its dequeue.
      if (t_ns > now) {
        ++stats_.future_stamps;
        t_ns = now;
      }
    } else if (!warned_timestamps_) {
      warned_timestamps_ = true;
      reportf(diagnostics_, Severity::kWarning, kCameraComponent,
              "'%s' gives no monotonic time stamps (flags 0x%X): using the dequeue time",
              config_.device.c_str(), static_cast<unsigned>(buf.flags));
    }
    if (has_device_seq_ && buf.sequence > last_device_seq_ + 1) {
      stats_.device_dropped += buf.sequence - last_device_seq_ - 1;
    }
    has_device_seq_ = true;
    last_device_seq_ = buf.sequence;

    const auto needed =
        static_cast<std::size_t>(format_.stride) * static_cast<std::size_t>(format_.height - 1) +
        static_cast<std::size_t>(format_.width * (format_.fourcc == V4L2_PIX_FMT_YUYV ? 2 : 1));
    bool deliver = false;
    if (buf.index >= buffers_.size() || (buf.flags & V4L2_BUF_FLAG_ERROR) != 0 ||
        buf.bytesused < needed || buffers_[buf.index].length < needed) {
      ++stats_.dropped_error;
    } else if (!accept_frame(t_ns)) {
      ++stats_.dropped_rate;
    } else {
      extract_luma(static_cast<const std::uint8_t*>(buffers_[buf.index].data), format_.width,
                   format_.height, format_.stride,
                   format_.fourcc == V4L2_PIX_FMT_YUYV ? PixelLayout::kYuyv : PixelLayout::kGrey,
                   format_.scale, image_.data());
      deliver = true;
    }
    if (os_.ioctl(fd_, VIDIOC_QBUF, &buf) < 0) {
      fail_and_reopen("re-queueing a buffer failed", errno);
      return false;
    }
    if (deliver) {
      ++stats_.delivered;
      out = hal::SensorEvent{};
      out.kind = hal::SensorEvent::Kind::kFrame;
      out.frame.t_ns = t_ns;
      out.frame.seq = seq_++;
      out.frame.image = hal::GrayImageView{image_.data(), kWidth, kHeight, kWidth};
      return true;
    }
  }
  return false;
}

}  // namespace cleanslam::drivers
