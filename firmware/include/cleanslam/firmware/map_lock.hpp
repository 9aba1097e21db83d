#pragma once

#include <string>
#include <utility>

namespace cleanslam::firmware {

// An advisory lock (flock, exclusive) on a map's lock file: one process writes a map file. The
// lock file is created when missing and never removed (removing it would let a third process lock
// a new file while the second still holds the old one); the holder writes "pid <pid> <program>"
// into it, so that a process refused can name the holder. The kernel releases the lock when the
// holder exits, however it ends (kill -9 included).
class MapLock {
 public:
  enum class Result {
    kHeld,   // this process holds it
    kBusy,   // another process holds it
    kError,  // the lock file could not be opened or locked
  };

  explicit MapLock(std::string path) : path_(std::move(path)) {}
  ~MapLock();
  MapLock(const MapLock&) = delete;
  MapLock& operator=(const MapLock&) = delete;

  // Takes the lock without waiting. Allocates nothing when it is taken; otherwise `why` says who
  // holds it (kBusy, e.g. "pid 1234 cleanslam") or what failed (kError, with the lock file named).
  Result acquire(std::string& why);
  [[nodiscard]] bool held() const { return fd_ >= 0; }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace cleanslam::firmware
