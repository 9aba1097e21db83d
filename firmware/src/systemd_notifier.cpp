#include "cleanslam/firmware/systemd_notifier.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace cleanslam::firmware {

SystemdNotifier::SystemdNotifier() {
  const char* socket_path = std::getenv("NOTIFY_SOCKET");
  if (socket_path == nullptr || socket_path[0] == '\0') {
    return;
  }
  long long usec = 0;
  if (const char* wd = std::getenv("WATCHDOG_USEC"); wd != nullptr) {
    usec = std::atoll(wd);
    if (const char* pid = std::getenv("WATCHDOG_PID");
        pid != nullptr && std::atoll(pid) != ::getpid()) {
      usec = 0;
    }
  }
  open(socket_path, usec);
}

SystemdNotifier::SystemdNotifier(const std::string& socket_path, long long watchdog_usec) {
  open(socket_path, watchdog_usec);
}

SystemdNotifier::~SystemdNotifier() {
  if (fd_ >= 0) {
    ::close(fd_);
  }
}

void SystemdNotifier::open(const std::string& socket_path, long long watchdog_usec) {
  if (socket_path.empty() || socket_path.size() >= sizeof(sockaddr_un::sun_path)) {
    return;
  }
  path_ = socket_path;
  fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (watchdog_usec > 0) {
    watchdog_period_ns_ = static_cast<hal::TimeNs>(watchdog_usec) * 1000 / 2;
  }
}

void SystemdNotifier::send(const char* message) {
  if (fd_ < 0) {
    return;
  }
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::memcpy(addr.sun_path, path_.data(), path_.size());
  if (addr.sun_path[0] == '@') {
    addr.sun_path[0] = '\0';
  }
  const auto len = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + path_.size());
  if (::sendto(fd_, message, std::strlen(message), MSG_NOSIGNAL,
               reinterpret_cast<const sockaddr*>(&addr), len) >= 0) {
    ++sent_;
  }
}

}  // namespace cleanslam::firmware
