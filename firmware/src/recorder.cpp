#include "cleanslam/firmware/recorder.hpp"
#include "cleanslam/firmware/rotating_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace cleanslam::firmware {

namespace lf = hal::log;

Recorder::~Recorder() {
  close();
}

bool Recorder::open(const RecorderOptions& options, std::string_view config_text,
                    std::string& error) {
  close();
  options_ = options;
  if (options_.max_files < 1) {
    options_.max_files = 1;
  }
  config_text_ = std::string(config_text);
  if (config_text_.size() + 8 > lf::kMaxPayload) {
    error = options_.path + ": configuration too large to record";
    return false;
  }
  names_ = rotation_names(options_.path, options_.max_files);
  ring_.assign(std::max<std::size_t>(options_.buffer_bytes, 128U << 10), 0);
  scratch_.assign(lf::kMaxPayload + lf::kRecordHeaderSize, 0);
  head_ = 0;
  size_ = 0;
  frames_seen_ = 0;
  stats_ = RecorderStats{};
  failing_ = false;
  if (!open_file(0)) {
    error = options_.path + ": cannot create the log: " + std::strerror(errno);
    return false;
  }
  return true;
}

bool Recorder::open_file(std::uint32_t file_index) {
  fd_ = ::open(names_[0].c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    return false;
  }
  struct stat st {};
  rotatable_ = ::fstat(fd_, &st) == 0 && S_ISREG(st.st_mode);
  file_bytes_ = 0;
  const bool was_rotating = rotating_;
  rotating_ = true;
  std::uint8_t header[lf::kFileHeaderSize];
  lf::ByteWriter w(header, sizeof header);
  lf::write_file_header(w, file_index);
  push(header, w.size());
  file_bytes_ += w.size();
  const std::uint64_t hash = lf::fnv1a64(config_text_.data(), config_text_.size());
  append(lf::RecordType::kConfig, 8 + config_text_.size(), [&](lf::ByteWriter& pw) {
    pw.u64(hash);
    pw.bytes(config_text_.data(), config_text_.size());
  });
  header_bytes_ = file_bytes_;
  rotating_ = was_rotating;
  return true;
}

void Recorder::push(const std::uint8_t* data, std::size_t n) {
  std::size_t tail = (head_ + size_) % ring_.size();
  const std::size_t first = std::min(n, ring_.size() - tail);
  std::memcpy(ring_.data() + tail, data, first);
  std::memcpy(ring_.data(), data + first, n - first);
  size_ += n;
}

template <typename Encode>
void Recorder::append(lf::RecordType type, std::size_t payload_size, const Encode& encode) {
  if (fd_ < 0) {
    return;
  }
  const std::size_t total = lf::kRecordHeaderSize + payload_size;
  if (payload_size > lf::kMaxPayload || total > ring_.size()) {
    ++stats_.dropped_buffer_full;
    return;
  }
  if (!rotating_ && rotatable_ && file_bytes_ > header_bytes_ &&
      file_bytes_ + total > options_.max_file_bytes) {
    rotate();
    if (fd_ < 0) {
      return;
    }
  }
  if (ring_.size() - size_ < total) {
    write_some();
    if (ring_.size() - size_ < total) {
      ++(failing_ ? stats_.dropped_write_failed : stats_.dropped_buffer_full);
      return;
    }
  }
  lf::ByteWriter w(scratch_.data() + lf::kRecordHeaderSize, payload_size);
  encode(w);
  lf::seal_record(scratch_.data(), type, static_cast<std::uint32_t>(payload_size));
  push(scratch_.data(), total);
  file_bytes_ += total;
  ++stats_.records;
}

void Recorder::clock(hal::TimeNs now) {
  append(lf::RecordType::kClock, 8, [&](lf::ByteWriter& w) { w.i64(now); });
}
void Recorder::gyro(const hal::GyroSample& s) {
  append(lf::RecordType::kGyro, lf::kGyroPayload, [&](lf::ByteWriter& w) { lf::encode(w, s); });
}
void Recorder::encoder(const hal::EncoderSample& s) {
  append(lf::RecordType::kEncoder, lf::kEncoderPayload,
         [&](lf::ByteWriter& w) { lf::encode(w, s); });
}
void Recorder::frame(const hal::CameraFrame& f) {
  const std::uint64_t k = frames_seen_++;
  if (options_.frame_every <= 0 || k % static_cast<std::uint64_t>(options_.frame_every) != 0) {
    ++stats_.frames_skipped;
    return;
  }
  append(lf::RecordType::kFrame, lf::frame_payload_size(f),
         [&](lf::ByteWriter& w) { lf::encode(w, f); });
}
void Recorder::lift(hal::TimeNs t_ns, bool lifted) {
  append(lf::RecordType::kLift, lf::kLiftPayload,
         [&](lf::ByteWriter& w) { lf::encode_lift(w, t_ns, lifted); });
}
void Recorder::pose(const hal::PoseEstimate& p) {
  append(lf::RecordType::kPose, lf::kPosePayload, [&](lf::ByteWriter& w) { lf::encode(w, p); });
}
void Recorder::update(const lf::UpdateRecord& u) {
  append(lf::RecordType::kUpdate, lf::kUpdatePayload, [&](lf::ByteWriter& w) { lf::encode(w, u); });
}

std::size_t Recorder::write_segment(std::size_t max_bytes) {
  const std::size_t n = std::min({size_, ring_.size() - head_, max_bytes});
  if (n == 0 || fd_ < 0) {
    return 0;
  }
  const ssize_t written = ::write(fd_, ring_.data() + head_, n);
  if (written <= 0) {
    if (written < 0 && errno != EINTR && errno != EAGAIN) {
      write_failed(errno);
    }
    return 0;
  }
  failing_ = false;
  const auto w = static_cast<std::size_t>(written);
  head_ = (head_ + w) % ring_.size();
  size_ -= w;
  stats_.bytes_written += w;
  return w;
}

void Recorder::write_some() {
  std::size_t budget = options_.write_chunk_bytes;
  while (budget > 0 && size_ > 0) {
    const std::size_t w = write_segment(budget);
    if (w == 0) {
      break;
    }
    budget -= w;
  }
}

void Recorder::flush(bool sync) {
  while (size_ > 0) {
    if (write_segment(size_) == 0) {
      break;
    }
  }
  if (sync && fd_ >= 0 && rotatable_ && ::fsync(fd_) != 0) {
    write_failed(errno);
  }
}

void Recorder::rotate() {
  rotating_ = true;
  flush(false);
  ::close(fd_);
  fd_ = -1;
  shift_rotation_names(names_);
  if (!open_file(static_cast<std::uint32_t>(stats_.rotations + 1))) {
    write_failed(errno);
  }
  ++stats_.rotations;
  rotating_ = false;
}

void Recorder::write_failed(int e) {
  ++stats_.write_errors;
  failing_ = true;
  if (stats_.first_write_errno == 0) {
    stats_.first_write_errno = e != 0 ? e : EIO;
  }
}

std::string Recorder::write_error() const {
  if (stats_.first_write_errno == 0) {
    return {};
  }
  return options_.path + ": cannot write: " + std::strerror(stats_.first_write_errno) + "; " +
         std::to_string(stats_.write_errors) + " failed write(s), " +
         std::to_string(stats_.dropped_write_failed) + " record(s) dropped, " +
         std::to_string(size_) + " byte(s) never written: the recording is incomplete";
}

void Recorder::close() {
  if (fd_ >= 0) {
    flush(true);
    ::close(fd_);
    fd_ = -1;
  }
}

}  // namespace cleanslam::firmware
