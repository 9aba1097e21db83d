#pragma once

#include "cleanslam/drivers/os.hpp"
#include "cleanslam/hal/time.hpp"

namespace cleanslam::drivers {

// One descriptor that stays the same while a device is closed and reopened: an epoll set holding
// the device's descriptor and a back-off timer. The loop polls fd(); it becomes readable when the
// device has data or the timer has fired.
class Readiness {
 public:
  explicit Readiness(Os& os);
  ~Readiness();
  Readiness(const Readiness&) = delete;
  Readiness& operator=(const Readiness&) = delete;

  [[nodiscard]] int fd() const { return epoll_fd_; }
  void watch(int fd);
  void unwatch(int fd);
  void arm_timer(hal::TimeNs delay_ns);
  void disarm_timer();
  // True (once) when the armed timer has fired.
  bool timer_fired();

 private:
  Os& os_;
  int epoll_fd_ = -1;
  int timer_fd_ = -1;
  bool armed_ = false;
  hal::TimeNs due_ns_ = 0;
};

// Exponential back-off between reopen attempts.
class Backoff {
 public:
  Backoff(hal::TimeNs min_ns, hal::TimeNs max_ns)
      : min_ns_(min_ns), max_ns_(max_ns), next_ns_(min_ns) {}
  hal::TimeNs next() {
    const hal::TimeNs delay = next_ns_;
    next_ns_ = next_ns_ * 2 > max_ns_ ? max_ns_ : next_ns_ * 2;
    return delay;
  }
  void reset() { next_ns_ = min_ns_; }

 private:
  hal::TimeNs min_ns_;
  hal::TimeNs max_ns_;
  hal::TimeNs next_ns_;
};

// Lets a repeated complaint through at most once per period; counts the ones held back.
class RateLimit {
 public:
  explicit RateLimit(hal::TimeNs period_ns) : period_ns_(period_ns) {}
  bool allow(hal::TimeNs now_ns) {
    if (has_last_ && now_ns - last_ns_ < period_ns_) {
      ++suppressed_;
      return false;
    }
    has_last_ = true;
    last_ns_ = now_ns;
    return true;
  }
  // Messages held back since the last one let through; resets the count.
  unsigned long take_suppressed() {
    const unsigned long n = suppressed_;
    suppressed_ = 0;
    return n;
  }

 private:
  hal::TimeNs period_ns_;
  hal::TimeNs last_ns_ = 0;
  bool has_last_ = false;
  unsigned long suppressed_ = 0;
};

}  // namespace cleanslam::drivers
