#include "cleanslam/drivers/readiness.hpp"

namespace cleanslam::drivers {

Readiness::Readiness(Os& os) : os_(os) {
  epoll_fd_ = os_.epoll_create();
  timer_fd_ = os_.timer_create();
  if (epoll_fd_ >= 0 && timer_fd_ >= 0) {
    os_.epoll_add(epoll_fd_, timer_fd_);
  }
}

Readiness::~Readiness() {
  if (timer_fd_ >= 0) {
    os_.close(timer_fd_);
  }
  if (epoll_fd_ >= 0) {
    os_.close(epoll_fd_);
  }
}

void Readiness::watch(int fd) {
  if (epoll_fd_ >= 0 && fd >= 0) {
    os_.epoll_add(epoll_fd_, fd);
  }
}

void Readiness::unwatch(int fd) {
  if (epoll_fd_ >= 0 && fd >= 0) {
    os_.epoll_remove(epoll_fd_, fd);
  }
}

void Readiness::arm_timer(hal::TimeNs delay_ns) {
  armed_ = true;
  due_ns_ = os_.monotonic_now() + delay_ns;
  if (timer_fd_ >= 0) {
    os_.timer_arm(timer_fd_, delay_ns > 0 ? delay_ns : 1);
  }
}

void Readiness::disarm_timer() {
  armed_ = false;
  if (timer_fd_ >= 0) {
    os_.timer_arm(timer_fd_, 0);
  }
}

bool Readiness::timer_fired() {
  if (!armed_ || os_.monotonic_now() < due_ns_) {
    return false;
  }
  disarm_timer();
  return true;
}

}  // namespace cleanslam::drivers
