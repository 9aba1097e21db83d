#include <fcntl.h>
#include <net/if.h>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>

#include "cleanslam/drivers/os.hpp"

namespace cleanslam::drivers {
namespace {

hal::TimeNs clock_ns(clockid_t clock) {
  timespec ts{};
  ::clock_gettime(clock, &ts);
  return static_cast<hal::TimeNs>(ts.tv_sec) * hal::kNsPerSecond + ts.tv_nsec;
}

class LinuxOs final : public Os {
 public:
  int open(const char* path, int flags) override { return ::open(path, flags | O_CLOEXEC); }
  int close(int fd) override { return ::close(fd); }
  int ioctl(int fd, unsigned long request, void* arg) override {
    int r = 0;
    do {
      r = ::ioctl(fd, request, arg);
    } while (r < 0 && errno == EINTR);
    return r;
  }
  void* mmap(std::size_t length, int prot, int flags, int fd, off_t offset) override {
    return ::mmap(nullptr, length, prot, flags, fd, offset);
  }
  int munmap(void* address, std::size_t length) override { return ::munmap(address, length); }
  ssize_t read(int fd, void* data, std::size_t size) override { return ::read(fd, data, size); }
  ssize_t write(int fd, const void* data, std::size_t size) override {
    return ::write(fd, data, size);
  }
  int socket(int domain, int type, int protocol) override {
    return ::socket(domain, type | SOCK_CLOEXEC, protocol);
  }
  int bind(int fd, const sockaddr* address, socklen_t length) override {
    return ::bind(fd, address, length);
  }
  int setsockopt(int fd, int level, int name, const void* value, socklen_t length) override {
    return ::setsockopt(fd, level, name, value, length);
  }
  unsigned int if_nametoindex(const char* name) override { return ::if_nametoindex(name); }
  ssize_t recvmsg(int fd, msghdr* message, int flags) override {
    return ::recvmsg(fd, message, flags);
  }
  int epoll_create() override { return ::epoll_create1(EPOLL_CLOEXEC); }
  int epoll_add(int epoll_fd, int fd) override {
    epoll_event event{};
    event.events = EPOLLIN;
    event.data.fd = fd;
    return ::epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &event);
  }
  int epoll_remove(int epoll_fd, int fd) override {
    return ::epoll_ctl(epoll_fd, EPOLL_CTL_DEL, fd, nullptr);
  }
  int timer_create() override {
    return ::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
  }
  int timer_arm(int timer_fd, hal::TimeNs delay_ns) override {
    itimerspec spec{};
    spec.it_value.tv_sec = static_cast<time_t>(delay_ns / hal::kNsPerSecond);
    spec.it_value.tv_nsec = static_cast<long>(delay_ns % hal::kNsPerSecond);
    std::uint64_t expirations = 0;
    while (::read(timer_fd, &expirations, sizeof expirations) > 0) {
    }
    return ::timerfd_settime(timer_fd, 0, &spec, nullptr);
  }
  bool poll_readable(int fd, hal::TimeNs timeout_ns) override {
    pollfd p{fd, POLLIN, 0};
    const int timeout_ms = static_cast<int>(timeout_ns / hal::kNsPerMillisecond);
    return ::poll(&p, 1, timeout_ms) > 0 && (p.revents & POLLIN) != 0;
  }
  [[nodiscard]] hal::TimeNs monotonic_now() const override { return clock_ns(CLOCK_MONOTONIC); }
  [[nodiscard]] hal::TimeNs realtime_now() const override { return clock_ns(CLOCK_REALTIME); }
};

}  // namespace

Os& linux_os() {
  static LinuxOs os;
  return os;
}

}  // namespace cleanslam::drivers
