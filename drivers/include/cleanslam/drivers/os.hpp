#pragma once

#include <sys/socket.h>
#include <sys/types.h>

#include <cstddef>

#include "cleanslam/hal/time.hpp"

namespace cleanslam::drivers {

// The system-call seam. Drivers make every kernel call through it, so unit tests can put a fake
// kernel behind it. Calls return what the system call returns and set errno on failure.
class Os {
 public:
  virtual ~Os() = default;

  virtual int open(const char* path, int flags) = 0;
  virtual int close(int fd) = 0;
  virtual int ioctl(int fd, unsigned long request, void* arg) = 0;
  virtual void* mmap(std::size_t length, int prot, int flags, int fd, off_t offset) = 0;
  virtual int munmap(void* address, std::size_t length) = 0;
  virtual ssize_t read(int fd, void* data, std::size_t size) = 0;
  virtual ssize_t write(int fd, const void* data, std::size_t size) = 0;

  virtual int socket(int domain, int type, int protocol) = 0;
  virtual int bind(int fd, const sockaddr* address, socklen_t length) = 0;
  virtual int setsockopt(int fd, int level, int name, const void* value, socklen_t length) = 0;
  virtual unsigned int if_nametoindex(const char* name) = 0;
  virtual ssize_t recvmsg(int fd, msghdr* message, int flags) = 0;

  // Readiness: an epoll set (readable when one of its members is) and one-shot timers.
  virtual int epoll_create() = 0;
  virtual int epoll_add(int epoll_fd, int fd) = 0;
  virtual int epoll_remove(int epoll_fd, int fd) = 0;
  virtual int timer_create() = 0;
  // Arms the timer to fire once after `delay_ns`; 0 disarms it.
  virtual int timer_arm(int timer_fd, hal::TimeNs delay_ns) = 0;
  // Non-blocking wait for `fd` to become readable; true when it is.
  virtual bool poll_readable(int fd, hal::TimeNs timeout_ns) = 0;

  [[nodiscard]] virtual hal::TimeNs monotonic_now() const = 0;
  [[nodiscard]] virtual hal::TimeNs realtime_now() const = 0;
};

// The running kernel.
Os& linux_os();

}  // namespace cleanslam::drivers
