#pragma once

#include <csignal>

#include "cleanslam/firmware/clocks.hpp"
#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/readers/log_source.hpp"

namespace cleanslam::firmware {

// SIGTERM and SIGINT request a clean stop. While an instance lives the two signals are blocked
// except inside the runners' waits (ppoll), so a stop is never lost between check and wait.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  [[nodiscard]] static bool requested();
  static void reset();
  [[nodiscard]] const sigset_t& wait_mask() const { return wait_mask_; }

 private:
  sigset_t old_mask_{};
  sigset_t wait_mask_{};
  struct sigaction old_term_ {};
  struct sigaction old_int_ {};
};

enum class RunEnd { kStopped, kSourcesExhausted };

// Work a runner does after each loop iteration (the status LED, saving the map); it reads the
// loop and changes nothing in it.
class LiveTask {
 public:
  virtual ~LiveTask() = default;
  virtual void run(const Loop& loop, hal::TimeNs now) = 0;
  // When run() is due again regardless of the loop, -1: after the loop's next iteration.
  [[nodiscard]] virtual hal::TimeNs next_due_ns() const = 0;
};

// Two tasks (either may be null), run one after the other; due when the earlier one is.
class TaskPair final : public LiveTask {
 public:
  TaskPair(LiveTask* first, LiveTask* second) : first_(first), second_(second) {}
  void run(const Loop& loop, hal::TimeNs now) override;
  [[nodiscard]] hal::TimeNs next_due_ns() const override;

 private:
  LiveTask* first_;
  LiveTask* second_;
};

// The robot: waits in ppoll() on the sources' descriptors until the next deadline (the loop's or
// the task's), then iterates on the monotonic clock and runs the task.
RunEnd run_live(Loop& loop, const hal::Clock& clock, const StopSignals& signals,
                LiveTask* task = nullptr);

// Datasets and logs on a virtual clock: the clock jumps to the next event or deadline. With
// `realtime`, each jump waits for the same span of wall-clock time. The task runs after each
// iteration, at its time; its next_due_ns() adds no iteration.
RunEnd run_virtual(Loop& loop, VirtualClock& clock, bool realtime, const StopSignals* signals,
                   LiveTask* task = nullptr);

// Bit-exact replay: iterates at the recorded iteration times, each with the events the recording
// loop ingested in it.
RunEnd run_recorded(Loop& loop, VirtualClock& clock, readers::LogSource& log,
                    const StopSignals* signals);

}  // namespace cleanslam::firmware
