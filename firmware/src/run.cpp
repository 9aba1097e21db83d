#include "cleanslam/firmware/run.hpp"

#include <poll.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <csignal>
#include <limits>

namespace cleanslam::firmware {

namespace {

volatile std::sig_atomic_t g_stop = 0;

extern "C" void on_stop_signal(int /*signo*/) {
  g_stop = 1;
}

timespec to_timespec(hal::TimeNs ns) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / hal::kNsPerSecond);
  ts.tv_nsec = static_cast<long>(ns % hal::kNsPerSecond);
  return ts;
}

bool all_exhausted(const Loop& loop) {
  const auto& s = loop.sources();
  return !s.empty() &&
         std::all_of(s.begin(), s.end(), [](const hal::SensorSource* x) { return x->exhausted(); });
}

// Lets a blocked SIGTERM/SIGINT in when the runner never waits (as fast as possible).
bool stop_requested(const StopSignals* signals) {
  if (signals == nullptr) {
    return false;
  }
  const timespec zero{};
  ::ppoll(nullptr, 0, &zero, &signals->wait_mask());
  return StopSignals::requested();
}

}  // namespace

StopSignals::StopSignals() {
  g_stop = 0;
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGTERM, &sa, &old_term_);
  sigaction(SIGINT, &sa, &old_int_);
  sigset_t block;
  sigemptyset(&block);
  sigaddset(&block, SIGTERM);
  sigaddset(&block, SIGINT);
  sigprocmask(SIG_BLOCK, &block, &old_mask_);
  wait_mask_ = old_mask_;
  sigdelset(&wait_mask_, SIGTERM);
  sigdelset(&wait_mask_, SIGINT);
}

StopSignals::~StopSignals() {
  sigprocmask(SIG_SETMASK, &old_mask_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
  sigaction(SIGINT, &old_int_, nullptr);
}

bool StopSignals::requested() {
  return g_stop != 0;
}

void StopSignals::reset() {
  g_stop = 0;
}

RunEnd run_live(Loop& loop, const hal::Clock& clock, const StopSignals& signals, LiveTask* task) {
  constexpr std::size_t kMaxFds = 16;
  std::array<pollfd, kMaxFds> fds{};
  nfds_t n = 0;
  for (const hal::SensorSource* s : loop.sources()) {
    if (s->fd() >= 0 && n < kMaxFds) {
      fds[n++] = pollfd{s->fd(), POLLIN, 0};
    }
  }
  loop.start(clock.now());
  if (task != nullptr) {
    task->run(loop, clock.now());
  }
  RunEnd end = RunEnd::kStopped;
  while (!StopSignals::requested()) {
    const hal::TimeNs now = clock.now();
    hal::TimeNs deadline = loop.next_deadline();
    if (task != nullptr && task->next_due_ns() >= 0) {
      deadline = std::min(deadline, task->next_due_ns());
    }
    const hal::TimeNs wait = std::max<hal::TimeNs>(0, deadline - now);
    const timespec ts = to_timespec(std::min<hal::TimeNs>(wait, hal::kNsPerSecond));
    ::ppoll(fds.data(), n, &ts, &signals.wait_mask());
    if (StopSignals::requested()) {
      break;
    }
    loop.iterate(clock.now());
    if (task != nullptr) {
      task->run(loop, clock.now());
    }
    if (all_exhausted(loop) && !loop.frame_work_pending()) {
      end = RunEnd::kSourcesExhausted;
      break;
    }
  }
  loop.finish();
  return end;
}

void TaskPair::run(const Loop& loop, hal::TimeNs now) {
  if (first_ != nullptr) {
    first_->run(loop, now);
  }
  if (second_ != nullptr) {
    second_->run(loop, now);
  }
}

hal::TimeNs TaskPair::next_due_ns() const {
  const hal::TimeNs a = first_ != nullptr ? first_->next_due_ns() : -1;
  const hal::TimeNs b = second_ != nullptr ? second_->next_due_ns() : -1;
  return a < 0 ? b : (b < 0 ? a : std::min(a, b));
}

RunEnd run_virtual(Loop& loop, VirtualClock& clock, bool realtime, const StopSignals* signals,
                   LiveTask* task) {
  const auto next_event = [&loop] {
    hal::TimeNs t = -1;
    for (const hal::SensorSource* s : loop.sources()) {
      const hal::TimeNs e = s->next_event_time();
      if (e >= 0 && (t < 0 || e < t)) {
        t = e;
      }
    }
    return t;
  };
  const hal::TimeNs t0 = std::max<hal::TimeNs>(0, next_event());
  clock.set(t0);
  loop.start(t0);
  MonotonicClock wall;
  const hal::TimeNs wall0 = wall.now();
  RunEnd end = RunEnd::kStopped;
  while (!stop_requested(signals)) {
    const hal::TimeNs event = next_event();
    if (event < 0 && all_exhausted(loop) && !loop.frame_work_pending()) {
      end = RunEnd::kSourcesExhausted;
      break;
    }
    hal::TimeNs t = loop.next_deadline();
    if (event > loop.span_end()) {
      t = clock.now();  // the loop refuses an event past the run's span at once
    } else if (event >= 0) {
      t = std::min(t, event);
    }
    t = std::max(t, clock.now());
    if (realtime) {
      const hal::TimeNs due = hal::add_saturated(wall0, hal::sub_saturated(t, t0));
      const hal::TimeNs now = wall.now();
      if (due > now) {
        const timespec ts = to_timespec(due - now);
        ::ppoll(nullptr, 0, &ts, signals != nullptr ? &signals->wait_mask() : nullptr);
        if (stop_requested(signals)) {
          break;
        }
      }
    }
    clock.set(t);
    loop.iterate(t);
    if (task != nullptr) {
      task->run(loop, t);
    }
  }
  loop.finish();
  return end;
}

RunEnd run_recorded(Loop& loop, VirtualClock& clock, readers::LogSource& log,
                    const StopSignals* signals) {
  const hal::TimeNs t0 = log.next_tick_time();
  if (t0 < 0) {
    loop.finish();
    return RunEnd::kSourcesExhausted;
  }
  log.advance_tick();
  clock.set(t0);
  loop.start(t0);
  RunEnd end = RunEnd::kSourcesExhausted;
  while (log.next_tick_time() >= 0) {
    if (stop_requested(signals)) {
      end = RunEnd::kStopped;
      break;
    }
    const hal::TimeNs t = log.next_tick_time();
    log.advance_tick();
    clock.set(t);
    loop.iterate(t);
  }
  loop.finish();
  return end;
}

}  // namespace cleanslam::firmware
