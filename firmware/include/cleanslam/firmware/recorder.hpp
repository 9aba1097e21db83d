#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "cleanslam/hal/frame.hpp"
#include "cleanslam/hal/log_format.hpp"
#include "cleanslam/hal/pose.hpp"
#include "cleanslam/hal/samples.hpp"

namespace cleanslam::firmware {

struct RecorderOptions {
  std::string path;                            // empty: no recording
  std::size_t max_file_bytes = 64U << 20;      // rotate beyond this
  int max_files = 4;                           // path, path.1 ... path.(max_files-1)
  int frame_every = 1;                         // record every k-th frame; 0: none
  std::size_t buffer_bytes = 4U << 20;         // records wait here for the disk
  std::size_t write_chunk_bytes = 256U << 10;  // at most this much is written per loop tick
};

struct RecorderStats {
  std::uint64_t records = 0;
  std::uint64_t dropped_buffer_full = 0;   // the disk did not keep up
  std::uint64_t dropped_write_failed = 0;  // the buffer was full because writing failed
  std::uint64_t frames_skipped = 0;        // frame_every > 1
  std::uint64_t bytes_written = 0;
  std::uint64_t rotations = 0;
  std::uint64_t write_errors = 0;
  int first_write_errno = 0;  // the errno of the first failed write, rotation or sync
};

// The binary log (hal/log_format.hpp). Appending copies a record into a ring buffer allocated
// at open(); write_some() moves a bounded chunk to the file, so the loop never waits for long.
// Each rotated file starts with the file header and the configuration record again.
class Recorder {
 public:
  Recorder() = default;
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  bool open(const RecorderOptions& options, std::string_view config_text, std::string& error);
  [[nodiscard]] bool is_open() const { return fd_ >= 0; }

  void clock(hal::TimeNs now);
  void gyro(const hal::GyroSample& s);
  void encoder(const hal::EncoderSample& s);
  void frame(const hal::CameraFrame& f);
  void lift(hal::TimeNs t_ns, bool lifted);
  void pose(const hal::PoseEstimate& p);
  void update(const hal::log::UpdateRecord& u);

  // Writes at most write_chunk_bytes of the pending records.
  void write_some();
  // Writes everything pending; with `sync`, also fsync()s the file.
  void flush(bool sync);
  void close();

  [[nodiscard]] const RecorderStats& stats() const { return stats_; }
  [[nodiscard]] std::size_t pending_bytes() const { return size_; }
  [[nodiscard]] bool frames_complete() const { return options_.frame_every == 1; }
  // After close(): "PATH: cannot write: STRERROR; N records dropped, M bytes never written" when
  // a write failed, else "".
  [[nodiscard]] std::string write_error() const;

 private:
  template <typename Encode>
  void append(hal::log::RecordType type, std::size_t payload_size, const Encode& encode);
  void push(const std::uint8_t* data, std::size_t n);
  bool open_file(std::uint32_t file_index);
  void rotate();
  void write_failed(int e);
  std::size_t write_segment(std::size_t max_bytes);

  RecorderOptions options_;
  std::vector<std::string> names_;  // path, path.1, ... (built at open: rotation allocates nothing)
  std::string config_text_;
  std::vector<std::uint8_t> ring_;
  std::vector<std::uint8_t> scratch_;
  std::size_t head_ = 0;
  std::size_t size_ = 0;
  std::size_t file_bytes_ = 0;  // bytes destined for the current file, pending ones included
  std::size_t header_bytes_ = 0;
  std::uint64_t frames_seen_ = 0;
  int fd_ = -1;
  bool rotating_ = false;
  bool failing_ = false;    // the last write failed: a full buffer is its consequence
  bool rotatable_ = false;  // a regular file (a device such as /dev/null is never renamed)
  RecorderStats stats_;
};

}  // namespace cleanslam::firmware
