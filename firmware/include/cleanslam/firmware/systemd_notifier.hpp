#pragma once

#include <string>

#include "cleanslam/firmware/loop.hpp"

namespace cleanslam::firmware {

// The sd_notify datagram protocol without libsystemd: "READY=1", "WATCHDOG=1", "STOPPING=1"
// sent to the unix datagram socket named by NOTIFY_SOCKET ('@' = abstract namespace). The
// watchdog is kicked at half of WATCHDOG_USEC when WATCHDOG_PID is unset or names this process.
class SystemdNotifier final : public Notifier {
 public:
  // Reads NOTIFY_SOCKET / WATCHDOG_USEC / WATCHDOG_PID; inactive without NOTIFY_SOCKET.
  SystemdNotifier();
  SystemdNotifier(const std::string& socket_path, long long watchdog_usec);
  ~SystemdNotifier() override;
  SystemdNotifier(const SystemdNotifier&) = delete;
  SystemdNotifier& operator=(const SystemdNotifier&) = delete;

  [[nodiscard]] bool active() const { return fd_ >= 0; }
  void ready() override { send("READY=1"); }
  void watchdog() override { send("WATCHDOG=1"); }
  void stopping() override { send("STOPPING=1"); }
  [[nodiscard]] hal::TimeNs watchdog_period_ns() const override { return watchdog_period_ns_; }
  [[nodiscard]] unsigned long long sent() const { return sent_; }

 private:
  void open(const std::string& socket_path, long long watchdog_usec);
  void send(const char* message);
  int fd_ = -1;
  std::string path_;
  hal::TimeNs watchdog_period_ns_ = 0;
  unsigned long long sent_ = 0;
};

}  // namespace cleanslam::firmware
