#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "cleanslam/firmware/estimator.hpp"
#include "cleanslam/firmware/health.hpp"
#include "cleanslam/firmware/recorder.hpp"
#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/interfaces.hpp"
#include "cleanslam/hal/log_format.hpp"

namespace cleanslam::firmware {

struct LoopOptions {
  double frame_rate_hz = 2.0;  // frames are accepted at most this often (1-2 Hz)
  double publish_rate_hz = 20.0;
  hal::TimeNs gyro_timeout_ns = 100 * hal::kNsPerMillisecond;
  hal::TimeNs encoder_timeout_ns = 250 * hal::kNsPerMillisecond;
  hal::TimeNs camera_timeout_ns = 3 * hal::kNsPerSecond;
  // A sample stamped more than max_time_skew_ns behind the clock, more than max_lead_ns ahead
  // of it, or past the start plus max_span_ns is a time jump.
  hal::TimeNs max_time_skew_ns = 1 * hal::kNsPerSecond;
  hal::TimeNs max_lead_ns = 10 * hal::kNsPerMillisecond;
  hal::TimeNs max_span_ns = hal::kDefaultMaxSpanNs;
  int frame_work_budget = 64;  // pipeline work units per loop iteration
  // The calibrated camera: a frame of another size is refused.
  hal::CameraCalibration camera;
};

// The per-update diagnostics records, as the frame pipeline finishes each frame.
class UpdateSink {
 public:
  virtual ~UpdateSink() = default;
  virtual void update(const hal::log::UpdateRecord& record) = 0;
  virtual void flush() {}
};

// The gyro samples the loop accepted (finite, in order, on time), as the estimator gets them.
class GyroSink {
 public:
  virtual ~GyroSink() = default;
  virtual void gyro(const hal::GyroSample& sample) = 0;
};

// Watchdog and readiness notifications (systemd).
class Notifier {
 public:
  virtual ~Notifier() = default;
  virtual void ready() = 0;
  virtual void watchdog() = 0;
  virtual void stopping() = 0;
  [[nodiscard]] virtual hal::TimeNs watchdog_period_ns() const = 0;  // 0: none
};

struct LoopStats {
  std::uint64_t iterations = 0;
  std::uint64_t gyro = 0;
  std::uint64_t encoders = 0;
  std::uint64_t frames_in = 0;
  std::uint64_t frames_done = 0;
  std::uint64_t predictions = 0;
  std::uint64_t predictions_skipped = 0;  // encoders silent
  std::uint64_t poses = 0;
  std::uint64_t update_records = 0;
  std::array<std::uint64_t, hal::log::kUpdateStatusCount> records_by_status{};
  RejectCounters rejects;
};

// The cooperative loop. Single-threaded; each iterate() ingests what the sources have ready and
// runs the tasks that are due, each bounded: dead reckoning, one budget of frame pipeline steps,
// publishing, health, watchdog, the recorder's write. Runners (run.hpp) decide when to iterate:
// poll() on the devices, a virtual clock, or the recorded iterations of a log.
// No heap allocation after the sources and sinks are added.
class Loop {
 public:
  Loop(const LoopOptions& options, Estimator& estimator);

  void add_source(hal::SensorSource* source);
  void add_pose_sink(hal::PoseSink* sink);
  void add_update_sink(UpdateSink* sink);
  void add_gyro_sink(GyroSink* sink);
  // Told the estimate and the dead-reckoning pose at each finished frame's time.
  void add_frame_sinks(hal::PoseSink* estimate, hal::PoseSink* dead_reckoning);
  void set_recorder(Recorder* recorder) { recorder_ = recorder; }
  void set_notifier(Notifier* notifier) { notifier_ = notifier; }
  void set_health_observer(HealthObserver* observer) { observer_ = observer; }

  void start(hal::TimeNs now);
  void iterate(hal::TimeNs now);
  // Earliest time a task is due; `now` or earlier when frame work is pending.
  [[nodiscard]] hal::TimeNs next_deadline() const;
  // The latest plausible event time: the start plus options.max_span_ns.
  [[nodiscard]] hal::TimeNs span_end() const {
    return hal::add_saturated(start_ns_, options_.max_span_ns);
  }
  [[nodiscard]] bool frame_work_pending() const {
    return active_ != nullptr || pending_ != nullptr;
  }
  // Flushes sinks and the recorder (fsync), tells systemd.
  void finish();

  [[nodiscard]] const std::vector<hal::SensorSource*>& sources() const { return sources_; }
  [[nodiscard]] const LoopStats& stats() const { return stats_; }
  [[nodiscard]] const Estimator& estimator() const { return estimator_; }
  [[nodiscard]] std::uint32_t health() const { return health_; }
  // Counts rejected inputs; the first of each reason is told to the health observer unless the
  // caller has told them already (`told`).
  void count(Reject r, std::uint64_t n = 1, bool told = false);

 private:
  struct FrameSlot {
    std::array<std::uint8_t, static_cast<std::size_t>(hal::kImageWidth) * hal::kImageHeight>
        pixels{};
    std::array<hal::FeatureObservation, hal::kMaxFeaturesPerFrame> features{};
    hal::CameraFrame frame;
  };

  void ingest(const hal::SensorEvent& ev, hal::TimeNs now);
  void ingest_gyro(const hal::GyroSample& s, hal::TimeNs now);
  void ingest_encoder(const hal::EncoderSample& s, hal::TimeNs now);
  void ingest_frame(const hal::CameraFrame& f, hal::TimeNs now);
  bool check_time(hal::TimeNs t, hal::TimeNs last, hal::TimeNs now);
  void run_dead_reckoning();
  void run_frame_steps();
  void publish(hal::TimeNs now);
  void update_health(hal::TimeNs now);

  LoopOptions options_;
  Estimator& estimator_;
  std::vector<hal::SensorSource*> sources_;
  std::vector<hal::PoseSink*> pose_sinks_;
  std::vector<UpdateSink*> update_sinks_;
  std::vector<GyroSink*> gyro_sinks_;
  std::vector<hal::PoseSink*> frame_sinks_;
  std::vector<hal::PoseSink*> frame_dr_sinks_;
  Recorder* recorder_ = nullptr;
  Notifier* notifier_ = nullptr;
  HealthObserver* observer_ = nullptr;

  hal::TimeNs start_ns_ = 0;
  hal::TimeNs now_ns_ = 0;
  std::uint32_t told_ = 0;  // bit per Reject: its first occurrence was told to the observer
  hal::TimeNs publish_period_ns_ = 0;
  hal::TimeNs frame_period_ns_ = 0;
  hal::TimeNs next_publish_ns_ = 0;
  hal::TimeNs next_watchdog_ns_ = -1;
  hal::TimeNs last_gyro_ns_ = -1;
  hal::TimeNs last_encoder_ns_ = -1;
  hal::TimeNs last_frame_ns_ = -1;           // last frame seen (camera alive)
  hal::TimeNs last_accepted_frame_ns_ = -1;  // last frame taken for processing
  bool odometry_pending_ = false;
  bool lifted_ = false;
  bool rejected_since_publish_ = false;
  std::uint32_t health_ = hal::kHealthOk;
  std::uint64_t recorder_dropped_seen_ = 0;

  std::array<FrameSlot, 2> slots_;
  FrameSlot* active_ = nullptr;   // being processed
  FrameSlot* pending_ = nullptr;  // newest waiting frame
  LoopStats stats_;
};

}  // namespace cleanslam::firmware
