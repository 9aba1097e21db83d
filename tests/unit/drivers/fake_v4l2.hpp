#pragma once

#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cstring>
#include <deque>
#include <set>
#include <string>
#include <vector>

#include "fake_os.hpp"

namespace cleanslam::drivers::testing {

// A fake V4L2 capture device behind the system-call seam.
class FakeV4l2 : public FakeOs {
 public:
  struct Size {
    std::uint32_t width;
    std::uint32_t height;
  };
  struct Ready {
    std::uint32_t index;
    hal::TimeNs t_ns;
    std::uint32_t flags;
    std::uint32_t sequence;
    std::uint32_t bytesused;
  };

  std::string path = "/dev/video0";
  bool present = true;
  std::uint32_t capabilities = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
  std::vector<std::uint32_t> formats{V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_GREY};
  std::vector<Size> sizes{{320, 240}, {640, 480}};
  std::uint32_t max_buffers = 8;
  bool supports_parm = true;
  int dqbuf_error = 0;
  std::uint32_t timestamp_flags = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;

  // State seen by tests.
  int device_fd = -1;
  v4l2_pix_format format{};
  std::vector<std::vector<std::uint8_t>> buffers;
  std::vector<std::uint32_t> queued;  // reserved: queueing allocates nothing
  std::deque<Ready> ready;
  bool streaming = false;
  int mapped = 0;
  std::uint32_t next_sequence = 0;

  FakeV4l2() { queued.reserve(64); }

  int open(const char* p, int) override {
    if (!present || path != p) {
      errno = ENOENT;
      return -1;
    }
    device_fd = new_fd();
    return device_fd;
  }
  int close(int fd) override {
    if (fd == device_fd) {
      device_fd = -1;
      streaming = false;
      buffers.clear();
      queued.clear();
      ready.clear();
    }
    return FakeOs::close(fd);
  }
  void* mmap(std::size_t length, int, int, int fd, off_t offset) override {
    const auto i = static_cast<std::size_t>(offset) / 0x10000;
    if (fd != device_fd || i >= buffers.size() || length != buffers[i].size()) {
      errno = EINVAL;
      return MAP_FAILED;
    }
    ++mapped;
    return buffers[i].data();
  }
  int munmap(void*, std::size_t) override {
    --mapped;
    return 0;
  }

  // The device fills the next queued buffer with `fill(x, y)` luma at `t_ns`.
  template <typename Fill>
  bool produce(hal::TimeNs t_ns, Fill fill, std::uint32_t flags = 0) {
    if (queued.empty()) {
      return false;
    }
    const std::uint32_t index = *queued.begin();
    queued.erase(queued.begin());
    auto& b = buffers[index];
    const bool yuyv = format.pixelformat == V4L2_PIX_FMT_YUYV;
    for (std::uint32_t y = 0; y < format.height; ++y) {
      for (std::uint32_t x = 0; x < format.width; ++x) {
        const auto v = static_cast<std::uint8_t>(fill(static_cast<int>(x), static_cast<int>(y)));
        if (yuyv) {
          b[y * format.bytesperline + 2 * x] = v;
          b[y * format.bytesperline + 2 * x + 1] = 128;
        } else {
          b[y * format.bytesperline + x] = v;
        }
      }
    }
    ready.push_back(Ready{index, t_ns, flags, next_sequence++, format.sizeimage});
    return true;
  }

  int ioctl(int fd, unsigned long request, void* arg) override {
    if (fd != device_fd) {
      errno = EBADF;
      return -1;
    }
    switch (request) {
      case VIDIOC_QUERYCAP: {
        auto* cap = static_cast<v4l2_capability*>(arg);
        *cap = v4l2_capability{};
        std::strcpy(reinterpret_cast<char*>(cap->driver), "fake");
        std::strcpy(reinterpret_cast<char*>(cap->card), "Fake Camera");
        cap->capabilities = capabilities | V4L2_CAP_DEVICE_CAPS;
        cap->device_caps = capabilities;
        return 0;
      }
      case VIDIOC_ENUM_FMT: {
        auto* d = static_cast<v4l2_fmtdesc*>(arg);
        if (d->index >= formats.size()) {
          errno = EINVAL;
          return -1;
        }
        d->pixelformat = formats[d->index];
        return 0;
      }
      case VIDIOC_ENUM_FRAMESIZES: {
        auto* f = static_cast<v4l2_frmsizeenum*>(arg);
        if (f->index >= sizes.size()) {
          errno = EINVAL;
          return -1;
        }
        f->type = V4L2_FRMSIZE_TYPE_DISCRETE;
        f->discrete.width = sizes[f->index].width;
        f->discrete.height = sizes[f->index].height;
        return 0;
      }
      case VIDIOC_S_FMT: {
        auto* f = static_cast<v4l2_format*>(arg);
        bool known = false;
        for (auto p : formats) {
          known = known || p == f->fmt.pix.pixelformat;
        }
        if (!known) {
          f->fmt.pix.pixelformat = formats.front();
        }
        Size chosen = sizes.front();
        for (auto s : sizes) {
          if (s.width == f->fmt.pix.width && s.height == f->fmt.pix.height) {
            chosen = s;
          }
        }
        f->fmt.pix.width = chosen.width;
        f->fmt.pix.height = chosen.height;
        const std::uint32_t bpp = f->fmt.pix.pixelformat == V4L2_PIX_FMT_YUYV ? 2 : 1;
        f->fmt.pix.bytesperline = chosen.width * bpp + 16;  // padded rows
        f->fmt.pix.sizeimage = f->fmt.pix.bytesperline * chosen.height;
        f->fmt.pix.field = V4L2_FIELD_NONE;
        format = f->fmt.pix;
        return 0;
      }
      case VIDIOC_S_PARM: {
        if (!supports_parm) {
          errno = ENOTTY;
          return -1;
        }
        auto* p = static_cast<v4l2_streamparm*>(arg);
        p->parm.capture.timeperframe = {1, 10};
        return 0;
      }
      case VIDIOC_REQBUFS: {
        auto* r = static_cast<v4l2_requestbuffers*>(arg);
        r->count = std::min(r->count, max_buffers);
        buffers.assign(r->count, std::vector<std::uint8_t>(format.sizeimage));
        return 0;
      }
      case VIDIOC_QUERYBUF: {
        auto* b = static_cast<v4l2_buffer*>(arg);
        b->length = static_cast<std::uint32_t>(buffers.at(b->index).size());
        b->m.offset = b->index * 0x10000;
        return 0;
      }
      case VIDIOC_QBUF: {
        queued.push_back(static_cast<v4l2_buffer*>(arg)->index);
        return 0;
      }
      case VIDIOC_DQBUF: {
        if (dqbuf_error != 0) {
          errno = dqbuf_error;
          return -1;
        }
        if (ready.empty() || !streaming) {
          errno = EAGAIN;
          return -1;
        }
        const Ready r = ready.front();
        ready.pop_front();
        auto* b = static_cast<v4l2_buffer*>(arg);
        b->index = r.index;
        b->flags = r.flags | timestamp_flags;
        b->sequence = r.sequence;
        b->bytesused = r.bytesused;
        b->timestamp.tv_sec = static_cast<time_t>(r.t_ns / hal::kNsPerSecond);
        b->timestamp.tv_usec = static_cast<suseconds_t>((r.t_ns % hal::kNsPerSecond) / 1000);
        return 0;
      }
      case VIDIOC_STREAMON:
        streaming = true;
        return 0;
      case VIDIOC_STREAMOFF:
        streaming = false;
        return 0;
      default:
        errno = ENOTTY;
        return -1;
    }
  }
};

}  // namespace cleanslam::drivers::testing
