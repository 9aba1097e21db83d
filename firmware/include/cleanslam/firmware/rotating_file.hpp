#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace cleanslam::firmware {

// When a text output starts a new file: as the recorder does (recorder.max_file_mb,
// recorder.max_files), the file is renamed PATH.1 (PATH.1 to PATH.2, ..., the oldest deleted)
// and PATH starts again. The default never rotates.
struct Rotation {
  std::size_t max_file_bytes = std::numeric_limits<std::size_t>::max();
  int max_files = 1;  // PATH, PATH.1 ... PATH.(max_files-1); 1: PATH is truncated instead
};

// PATH, PATH.1 ... PATH.(files-1): built once at open, so that a rotation allocates nothing.
std::vector<std::string> rotation_names(const std::string& path, int files);
// Deletes the oldest name and renames each to the next (PATH.1 to PATH.2, ..., PATH to PATH.1).
void shift_rotation_names(const std::vector<std::string>& names);

// A text output file (TUM, its covariance side file, diagnostics CSV) written through stdio with
// a buffer allocated at open(): bounded by its Rotation, and keeping the first write error (the
// file and strerror) instead of losing it in the stdio buffer. A file that is not a regular one
// (a device such as /dev/null) is never rotated. Writing and rotating allocate nothing.
class RotatingFile {
 public:
  RotatingFile() = default;
  ~RotatingFile();
  RotatingFile(const RotatingFile&) = delete;
  RotatingFile& operator=(const RotatingFile&) = delete;

  // Creates (truncates) PATH; false with `error` naming the file and the reason.
  bool open(const std::string& path, Rotation rotation, std::string& error);
  [[nodiscard]] bool is_open() const { return file_ != nullptr; }
  // Text in printf format, counted towards the file's size.
  void print(const char* format, ...) __attribute__((format(printf, 2, 3)));
  // The file holds at least max_file_bytes (rotate() before the next line).
  [[nodiscard]] bool full() const { return rotatable_ && bytes_ >= rotation_.max_file_bytes; }
  // Flushes PATH, shifts the names and starts PATH again, with `header` first.
  void rotate(const char* header);
  void flush();
  // Flushes and closes; false when any write failed.
  bool close();

  [[nodiscard]] const std::string& path() const { return names_.empty() ? empty_ : names_[0]; }
  [[nodiscard]] bool failed() const { return errno_ != 0; }
  // "PATH: cannot write: STRERROR" for the first failed write; "" when nothing failed.
  [[nodiscard]] std::string error() const;
  [[nodiscard]] std::uint64_t rotations() const { return rotations_; }
  [[nodiscard]] const Rotation& rotation() const { return rotation_; }

 private:
  void fail(int e);

  std::FILE* file_ = nullptr;
  std::vector<char> buffer_;
  std::vector<std::string> names_;  // PATH, PATH.1, ... (built at open: rotation allocates nothing)
  Rotation rotation_;
  bool rotatable_ = false;
  std::size_t bytes_ = 0;
  std::uint64_t rotations_ = 0;
  int errno_ = 0;
  std::string empty_;
};

}  // namespace cleanslam::firmware
