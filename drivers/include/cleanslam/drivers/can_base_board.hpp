#pragma once

#include <cstdint>
#include <string>

#include "cleanslam/drivers/can_messages.hpp"
#include "cleanslam/drivers/diagnostics.hpp"
#include "cleanslam/drivers/os.hpp"
#include "cleanslam/drivers/readiness.hpp"
#include "cleanslam/hal/interfaces.hpp"

namespace cleanslam::drivers {

struct CanBaseBoardConfig {
  std::string interface = "can0";
  hal::TimeNs reopen_min_ns = 100 * hal::kNsPerMillisecond;
  hal::TimeNs reopen_max_ns = 5 * hal::kNsPerSecond;
  // Frames handled per read() call at most, so one call stays bounded.
  int max_frames_per_read = 64;
};

struct CanBaseBoardStats {
  std::uint64_t frames = 0;
  std::uint64_t encoder_frames = 0;
  std::uint64_t gyro_frames = 0;
  std::uint64_t wrong_length = 0;
  std::uint64_t unknown_id = 0;
  std::uint64_t encoder_dropped = 0;  // missing from the sequence counter
  std::uint64_t gyro_dropped = 0;
  std::uint64_t duplicates = 0;
  std::uint64_t out_of_order = 0;
  std::uint64_t error_frames = 0;
  std::uint64_t bus_off = 0;
  std::uint64_t bus_off_recovered = 0;
  std::uint64_t controller_errors = 0;  // overflows, error-passive/warning states
  std::uint64_t gyro_saturated = 0;
  std::uint64_t opens = 0;
  std::uint64_t open_failures = 0;
  std::uint64_t receive_errors = 0;
  double gyro_temperature_c = 0.0;
};

// Gives a gyro sample a better time stamp than its CAN reception time (the data-ready line).
class GyroTimeReference {
 public:
  virtual ~GyroTimeReference() = default;
  // The sample's time for a gyro frame received at `received_ns`, when one is known.
  virtual bool sample_time(hal::TimeNs received_ns, hal::TimeNs& sample_ns) = 0;
};

// The base board on SocketCAN: a raw socket with kernel filters for the encoder and gyro frames
// and all error frames, kernel receive time stamps, sequence checks, reopen with back-off.
class CanBaseBoard final : public hal::SensorSource {
 public:
  explicit CanBaseBoard(CanBaseBoardConfig config, Os& os = linux_os(),
                        Diagnostics& diagnostics = stderr_diagnostics());
  ~CanBaseBoard() override;
  CanBaseBoard(const CanBaseBoard&) = delete;
  CanBaseBoard& operator=(const CanBaseBoard&) = delete;

  // Stable across reopens: readable when frames wait or a reopen is due.
  [[nodiscard]] int fd() const override { return readiness_.fd(); }
  bool read(hal::SensorEvent& out) override;

  [[nodiscard]] bool connected() const { return socket_ >= 0; }
  [[nodiscard]] bool bus_off() const { return bus_off_; }
  [[nodiscard]] const CanBaseBoardStats& stats() const { return stats_; }
  void set_gyro_time_reference(GyroTimeReference* reference) { time_reference_ = reference; }

 private:
  bool open_socket();
  void close_socket();
  void schedule_reopen();
  bool handle_frame(const can_map::Frame& frame, hal::TimeNs t_ns, hal::SensorEvent& out);
  void handle_error_frame(std::uint32_t can_id, const can_map::Frame& frame, hal::TimeNs t_ns);
  void note_recovered(hal::TimeNs t_ns, const char* how);
  bool sequence_ok(can_map::SequenceTracker& tracker, std::uint8_t seq, const char* what,
                   std::uint64_t& dropped, hal::TimeNs now);

  CanBaseBoardConfig config_;
  Os& os_;
  Diagnostics& diagnostics_;
  Readiness readiness_;
  Backoff backoff_;
  int socket_ = -1;
  bool bus_off_ = false;
  hal::TimeNs bus_off_since_ns_ = 0;
  CanBaseBoardStats stats_;
  can_map::SequenceTracker encoder_seq_;
  can_map::SequenceTracker gyro_seq_;
  can_map::TickExtender left_;
  can_map::TickExtender right_;
  GyroTimeReference* time_reference_ = nullptr;
  RateLimit malformed_limit_{10 * hal::kNsPerSecond};
  RateLimit gap_limit_{10 * hal::kNsPerSecond};
  RateLimit error_limit_{10 * hal::kNsPerSecond};
};

}  // namespace cleanslam::drivers
