#include "cleanslam/firmware/map_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

namespace cleanslam::firmware {

namespace {

// What the holder wrote: its first line, printable characters only.
std::string holder_of(int fd) {
  char text[96] = {};
  const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
  std::string s;
  for (ssize_t i = 0; i < n && text[i] != '\n'; ++i) {
    const char c = text[i];
    s += (c >= ' ' && c <= '~') ? c : '?';
  }
  return s.empty() ? std::string("a process that has not yet written its pid") : s;
}

}  // namespace

MapLock::~MapLock() {
  if (fd_ >= 0) {
    ::close(fd_);
  }
}

MapLock::Result MapLock::acquire(std::string& why) {
  if (fd_ >= 0) {
    return Result::kHeld;
  }
  // A lock file another user created may be readable only; flock needs no write access.
  int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd < 0 && (errno == EACCES || errno == EROFS)) {
    fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  }
  if (fd < 0) {
    why = path_ + ": cannot open the lock file: " + std::strerror(errno);
    return Result::kError;
  }
  while (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int e = errno;
    if (e == EINTR) {
      continue;
    }
    if (e == EWOULDBLOCK) {
      why = holder_of(fd);
      ::close(fd);
      return Result::kBusy;
    }
    ::close(fd);
    why = path_ + ": cannot lock: " + std::strerror(e);
    return Result::kError;
  }
  fd_ = fd;
  char text[96];
  const int n = std::snprintf(text, sizeof text, "pid %ld %s\n", static_cast<long>(::getpid()),
                              program_invocation_short_name);
  if (n > 0 && ::ftruncate(fd_, 0) == 0) {
    // Informative only: a lock file this process cannot write still locks.
    (void)!::pwrite(fd_, text, static_cast<std::size_t>(std::min(n, 95)), 0);
  }
  return Result::kHeld;
}

}  // namespace cleanslam::firmware
