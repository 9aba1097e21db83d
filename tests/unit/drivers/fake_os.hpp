#pragma once

#include <linux/can.h>
#include <linux/can/raw.h>
#include <sys/socket.h>

#include <cerrno>
#include <cstring>
#include <deque>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "cleanslam/drivers/diagnostics.hpp"
#include "cleanslam/drivers/os.hpp"
#include "time_units.hpp"

namespace cleanslam::drivers::testing {

using cleanslam::test::kMs;

// A fake kernel at the system-call seam: sockets fed from queues, clocks set by the test.
class FakeOs : public Os {
 public:
  struct Received {
    can_frame frame{};
    hal::TimeNs realtime_ns = -1;  // kernel time stamp, -1 for none
    int error = 0;                 // nonzero: recvmsg fails with this errno
    ssize_t bytes = sizeof(can_frame);
  };

  std::map<std::string, unsigned> interfaces{{"vcan0", 3}};
  std::deque<Received> inbox;
  std::vector<can_frame> sent;
  int write_error = 0;
  std::vector<can_filter> filters;
  can_err_mask_t error_mask = 0;
  bool timestamps_enabled = false;
  int bound_ifindex = -1;
  std::set<int> open_fds;
  std::set<int> epoll_members;
  hal::TimeNs timer_delay_ns = 0;
  hal::TimeNs mono_ns = 1'000 * hal::kNsPerSecond;
  hal::TimeNs realtime_offset_ns = 1'700'000'000 * hal::kNsPerSecond;
  int sockets_opened = 0;

  int new_fd() {
    const int fd = next_fd_++;
    open_fds.insert(fd);
    return fd;
  }

  int open(const char*, int) override {
    errno = ENOENT;
    return -1;
  }
  int close(int fd) override {
    open_fds.erase(fd);
    return 0;
  }
  int ioctl(int, unsigned long, void*) override {
    errno = ENOTTY;
    return -1;
  }
  void* mmap(std::size_t, int, int, int, off_t) override {
    errno = ENODEV;
    return reinterpret_cast<void*>(-1);
  }
  int munmap(void*, std::size_t) override { return 0; }
  ssize_t read(int, void*, std::size_t) override {
    errno = EAGAIN;
    return -1;
  }
  ssize_t write(int, const void* data, std::size_t size) override {
    if (write_error != 0) {
      errno = write_error;
      return -1;
    }
    can_frame f{};
    std::memcpy(&f, data, std::min(size, sizeof f));
    sent.push_back(f);
    return static_cast<ssize_t>(size);
  }
  int socket(int domain, int, int protocol) override {
    if (domain != PF_CAN || protocol != CAN_RAW) {
      errno = EAFNOSUPPORT;
      return -1;
    }
    ++sockets_opened;
    return new_fd();
  }
  int bind(int, const sockaddr* address, socklen_t) override {
    sockaddr_can a{};
    std::memcpy(&a, address, sizeof a);
    bound_ifindex = a.can_ifindex;
    return 0;
  }
  int setsockopt(int, int level, int name, const void* value, socklen_t length) override {
    if (level == SOL_CAN_RAW && name == CAN_RAW_FILTER) {
      filters.assign(static_cast<const can_filter*>(value),
                     static_cast<const can_filter*>(value) + length / sizeof(can_filter));
    } else if (level == SOL_CAN_RAW && name == CAN_RAW_ERR_FILTER) {
      std::memcpy(&error_mask, value, sizeof error_mask);
    } else if (level == SOL_SOCKET && name == SO_TIMESTAMPNS) {
      timestamps_enabled = true;
    }
    return 0;
  }
  unsigned int if_nametoindex(const char* name) override {
    const auto it = interfaces.find(name);
    if (it == interfaces.end()) {
      errno = ENODEV;
      return 0;
    }
    return it->second;
  }
  ssize_t recvmsg(int, msghdr* message, int) override {
    if (inbox.empty()) {
      errno = EAGAIN;
      return -1;
    }
    const Received r = inbox.front();
    inbox.pop_front();
    if (r.error != 0) {
      errno = r.error;
      return -1;
    }
    std::memcpy(message->msg_iov[0].iov_base, &r.frame, sizeof r.frame);
    cmsghdr* c = message->msg_controllen >= sizeof(cmsghdr)
                     ? static_cast<cmsghdr*>(message->msg_control)
                     : nullptr;
    if (r.realtime_ns >= 0 && timestamps_enabled && c != nullptr) {
      c->cmsg_level = SOL_SOCKET;
      c->cmsg_type = SCM_TIMESTAMPNS;
      c->cmsg_len = CMSG_LEN(sizeof(timespec));
      timespec ts{};
      ts.tv_sec = static_cast<time_t>(r.realtime_ns / hal::kNsPerSecond);
      ts.tv_nsec = static_cast<long>(r.realtime_ns % hal::kNsPerSecond);
      std::memcpy(CMSG_DATA(c), &ts, sizeof ts);
      message->msg_controllen = CMSG_SPACE(sizeof(timespec));
    } else {
      message->msg_controllen = 0;
    }
    return r.bytes;
  }
  int epoll_create() override { return new_fd(); }
  int epoll_add(int, int fd) override {
    epoll_members.insert(fd);
    return 0;
  }
  int epoll_remove(int, int fd) override {
    epoll_members.erase(fd);
    return 0;
  }
  int timer_create() override { return new_fd(); }
  int timer_arm(int, hal::TimeNs delay_ns) override {
    timer_delay_ns = delay_ns;
    return 0;
  }
  std::function<bool(int)> readable_hook;
  bool poll_readable(int fd, hal::TimeNs) override { return readable_hook && readable_hook(fd); }
  [[nodiscard]] hal::TimeNs monotonic_now() const override { return mono_ns; }
  [[nodiscard]] hal::TimeNs realtime_now() const override { return mono_ns + realtime_offset_ns; }

  // A frame the kernel stamped `age_ns` before now.
  void receive(std::uint32_t id, std::initializer_list<std::uint8_t> data, hal::TimeNs age_ns = 0) {
    Received r;
    r.frame.can_id = id;
    r.frame.len = static_cast<std::uint8_t>(data.size());
    std::copy(data.begin(), data.end(), r.frame.data);
    r.realtime_ns = realtime_now() - age_ns;
    inbox.push_back(r);
  }
  void receive_error(int error) {
    Received r;
    r.error = error;
    inbox.push_back(r);
  }

 private:
  int next_fd_ = 100;
};

// Keeps every message for the test to inspect.
class RecordingDiagnostics : public Diagnostics {
 public:
  struct Entry {
    Severity severity;
    std::string component;
    std::string message;
  };
  std::vector<Entry> entries;
  void report(Severity severity, std::string_view component, std::string_view message) override {
    entries.push_back({severity, std::string(component), std::string(message)});
  }
  [[nodiscard]] bool any_contains(const std::string& text) const {
    for (const auto& e : entries) {
      if (e.message.find(text) != std::string::npos) {
        return true;
      }
    }
    return false;
  }
  [[nodiscard]] std::string all() const {
    std::string s;
    for (const auto& e : entries) {
      s += e.component + ": " + e.message + "\n";
    }
    return s;
  }
};

}  // namespace cleanslam::drivers::testing
