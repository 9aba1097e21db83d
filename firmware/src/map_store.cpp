#include "cleanslam/firmware/map_store.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <utility>
#include <vector>

namespace cleanslam::firmware {

namespace mf = hal::map_file;

namespace {

std::string errno_text(int e) {
  return std::strerror(e);
}

// Writes all of `data`, across short writes and interrupted calls; false with errno set.
bool write_all(int fd, const std::uint8_t* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      return false;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

// Reads until end of file or `capacity` bytes; -1 with errno set on an error.
ssize_t read_up_to(int fd, std::uint8_t* data, std::size_t capacity) {
  std::size_t got = 0;
  while (got < capacity) {
    const ssize_t n = ::read(fd, data + got, capacity - got);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      return -1;
    }
    if (n == 0) {
      break;
    }
    got += static_cast<std::size_t>(n);
  }
  return static_cast<ssize_t>(got);
}

void print_saved(const char* program, const MapStore& store, const MapStore::Saved& saved) {
  const MapPaths& p = store.paths();
  std::fprintf(stderr, "%s: map: saved %d landmarks to %s%s%s (%zu KB)\n", program, saved.landmarks,
               p.path.c_str(), p.symlink() ? ", a link to " : "", p.symlink() ? p.file.c_str() : "",
               (saved.bytes + 512) / 1024);
}

constexpr const char* kNotSaved = ": it is kept as it is, and this run does not save its map";

}  // namespace

MapStore::MapStore(MapStoreOptions options)
    : options_(std::move(options)),
      paths_(map_paths(options_.path, static_cast<long>(::getpid()))),
      lock_(paths_.lock),
      interval_ns_(hal::from_seconds(options_.save_interval_s)),
      snapshot_(std::make_unique<mf::MapSnapshot>()),
      buffer_(mf::kMaxFileSize + 1) {}

void MapStore::refuse(StartCheck& c, const std::string& reason) {
  c.found = Found::kRefused;
  struct stat st {};
  const bool older = ::lstat(paths_.refused.c_str(), &st) == 0;
  if (std::rename(paths_.file.c_str(), paths_.refused.c_str()) != 0) {
    const int e = errno;
    c.found = Found::kUnreadable;
    saving_allowed_ = false;
    c.messages.push_back({true, paths_.file + ": refused: " + reason +
                                    "; it could not be moved to " + paths_.refused + ": " +
                                    errno_text(e) + kNotSaved});
    return;
  }
  c.messages.push_back({true, paths_.file + ": refused: " + reason + "; moved to " +
                                  paths_.refused + (older ? " (replacing an older one)" : "") +
                                  ": a new map starts"});
}

bool MapStore::lock(StartCheck& c) {
  lock_tried_ = true;
  std::string why;
  switch (lock_.acquire(why)) {
    case MapLock::Result::kHeld:
      return true;
    case MapLock::Result::kBusy:
      c.found = Found::kLocked;
      saving_allowed_ = false;
      locked_out_ = true;
      c.messages.push_back({false,
                            paths_.file + " is in use by another process (" + why + ", holding " +
                                paths_.lock +
                                "): two processes on one map would overwrite each other's "
                                "saves; this run does not start",
                            true});
      return false;
    case MapLock::Result::kError:
      c.messages.push_back({true, why + ": the map is saved without the lock, and temporary "
                                        "files of saves cut short are not removed"});
      return true;
  }
  return true;
}

void MapStore::remove_stale_temporaries(StartCheck& c) {
  const std::string base = std::filesystem::path(paths_.file).filename().string();
  std::error_code ec;
  std::vector<std::string> stale;
  for (const auto& entry : std::filesystem::directory_iterator(paths_.dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (is_map_temporary(name, base)) {
      stale.push_back(entry.path().string());
    }
  }
  for (const std::string& tmp : stale) {
    if (::unlink(tmp.c_str()) == 0) {
      c.messages.push_back({false, "removed " + tmp +
                                       ", a save cut short (power cut, crash or kill); the map "
                                       "saved before it is " +
                                       paths_.file});
    } else {
      c.messages.push_back(
          {true, tmp + ": a save cut short, could not be removed: " + errno_text(errno)});
    }
  }
}

MapStore::StartCheck MapStore::check_at_start() {
  StartCheck c;
  snapshot_->count = 0;
  if (!paths_.error.empty()) {
    c.found = Found::kUnreadable;
    saving_allowed_ = false;
    c.messages.push_back({true, options_.path + ": " + paths_.error + kNotSaved});
    return c;
  }
  if (paths_.symlink()) {
    struct stat st {};
    const bool dangling = ::lstat(paths_.file.c_str(), &st) != 0;
    c.messages.push_back({false, options_.path + " is a symbolic link to " + paths_.file +
                                     (dangling ? ", which does not exist yet" : "") +
                                     ": the map is read from and saved to " + paths_.file +
                                     ", and the link is kept"});
  }
  if (!lock(c)) {
    return c;
  }
  if (lock_.held()) {
    remove_stale_temporaries(c);
  }
  check_file(c);
  return c;
}

void MapStore::check_file(StartCheck& c) {
  const std::string& file = paths_.file;
  struct stat st {};
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);  // a FIFO must not block
  if (fd < 0) {
    const int e = errno;
    if (e == ENOENT) {
      c.messages.push_back({false, "no saved map at " + file + ": a new map"});
      if (::access(paths_.dir.c_str(), W_OK | X_OK) != 0) {
        c.messages.push_back(
            {true, paths_.dir + ": " + errno_text(errno) + ": the map cannot be saved to " + file});
      }
      return;
    }
    c.found = Found::kUnreadable;
    saving_allowed_ = false;
    c.messages.push_back({true, file + ": cannot open: " + errno_text(e) + kNotSaved});
    return;
  }
  std::string unreadable;
  ssize_t n = -1;
  if (::fstat(fd, &st) != 0) {
    unreadable = "cannot stat: " + errno_text(errno);
  } else if (!S_ISREG(st.st_mode)) {
    unreadable = "not a regular file";
  } else if (static_cast<std::uint64_t>(st.st_size) <= mf::kMaxFileSize) {
    n = read_up_to(fd, buffer_.data(), buffer_.size());
    if (n < 0) {
      unreadable = "cannot read: " + errno_text(errno);
    }
  }
  ::close(fd);
  if (!unreadable.empty()) {
    c.found = Found::kUnreadable;
    saving_allowed_ = false;
    c.messages.push_back({true, file + ": " + unreadable + kNotSaved});
    return;
  }
  if (n < 0 || static_cast<std::size_t>(n) > mf::kMaxFileSize) {
    c.decoded.refusal = mf::Refusal::kSize;
    c.decoded.offset = mf::kMaxFileSize;
    refuse(c, std::to_string(st.st_size) + " bytes, more than a map file holds (" +
                  std::to_string(mf::kMaxFileSize) + ")");
    return;
  }
  c.decoded = mf::decode(buffer_.data(), static_cast<std::size_t>(n), *snapshot_);
  if (c.decoded.refusal != mf::Refusal::kNone) {
    const std::string detail = c.decoded.detail.data();
    refuse(c, std::string(mf::to_string(c.decoded.refusal)) +
                  (detail.empty() ? std::string() : ": " + detail + ",") + " at byte " +
                  std::to_string(c.decoded.offset));
    return;
  }
  c.found = Found::kValid;
  char when[64];
  std::snprintf(when, sizeof when, "%.1f", hal::to_seconds(snapshot_->saved_at_ns));
  c.messages.push_back({false, file + ": a saved map of " + std::to_string(snapshot_->count) +
                                   " landmarks, saved at t=" + when + " s"});
  c.messages.push_back({false,
                        "starting from a saved map is not built yet: this run makes a new map, "
                        "which replaces " +
                            file + " at its first save"});
}

bool MapStore::save(const Estimator& estimator, hal::TimeNs t_ns, Saved& saved,
                    std::string& error) {
  if (!saving_allowed_) {
    error = options_.path + ": not saved: " +
            (locked_out_ ? "another process holds " + paths_.lock
                         : std::string("the file found at start is kept as it is"));
    return false;
  }
  if (!lock_tried_) {  // saving without the check at start: the lock is still needed
    lock_tried_ = true;
    std::string why;
    if (lock_.acquire(why) == MapLock::Result::kBusy) {
      saving_allowed_ = false;
      locked_out_ = true;
      error = paths_.file + ": not saved: another process holds " + paths_.lock + " (" + why + ")";
      return false;
    }
  }
  if (!estimator.map_snapshot(t_ns, *snapshot_)) {
    error = options_.path + ": not saved: the estimator keeps no map";
    return false;
  }
  const std::size_t size = mf::encode(*snapshot_, buffer_.data(), buffer_.size());
  if (size == 0) {
    error = options_.path + ": not saved: " + std::to_string(snapshot_->count) +
            " landmarks do not fit a map file";
    return false;
  }
  const std::string& file = paths_.file;
  const std::string& tmp = paths_.tmp;
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    error = tmp + ": cannot create: " + errno_text(errno) + "; " + file + " is unchanged";
    return false;
  }
  const char* failed = nullptr;
  if (!write_all(fd, buffer_.data(), size)) {
    failed = "cannot write";
  } else if (::fsync(fd) != 0) {
    failed = "cannot sync";
  }
  int e = errno;
  if (::close(fd) != 0 && failed == nullptr) {
    failed = "cannot close";
    e = errno;
  }
  if (failed == nullptr && std::rename(tmp.c_str(), file.c_str()) != 0) {
    e = errno;
    ::unlink(tmp.c_str());
    error =
        tmp + ": cannot rename onto " + file + ": " + errno_text(e) + "; " + file + " is unchanged";
    return false;
  }
  if (failed != nullptr) {
    ::unlink(tmp.c_str());
    error = tmp + ": " + failed + ": " + errno_text(e) + "; " + file + " is unchanged";
    return false;
  }
  const int dir = ::open(paths_.dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir < 0 || ::fsync(dir) != 0) {
    e = errno;
    if (dir >= 0) {
      ::close(dir);
    }
    error = paths_.dir + ": cannot sync the directory: " + errno_text(e) + "; " + file +
            " is written but may not survive a power cut";
    return false;
  }
  ::close(dir);
  saved.landmarks = snapshot_->count;
  saved.bytes = size;
  return true;
}

bool MapStore::due(hal::TimeNs t_ns) {
  if (next_due_ns_ < 0) {
    next_due_ns_ = hal::add_saturated(t_ns, interval_ns_);
    return false;
  }
  if (t_ns < next_due_ns_) {
    return false;
  }
  next_due_ns_ = hal::add_saturated(t_ns, interval_ns_);
  return true;
}

void PeriodicMapSave::run(const Loop& loop, hal::TimeNs now) {
  if (!store_.saving_allowed() || !store_.due(now)) {
    return;
  }
  MapStore::Saved saved;
  std::string error;
  if (store_.save(loop.estimator(), now, saved, error)) {
    print_saved(program_, store_, saved);
  } else {
    std::fprintf(stderr, "%s: warning: map: %s\n", program_, error.c_str());
  }
}

void print_start_check(const MapStore::StartCheck& check, const char* program) {
  for (const MapStore::Message& m : check.messages) {
    const char* level = m.error ? "error: " : m.warning ? "warning: " : "";
    std::fprintf(stderr, "%s: %smap: %s\n", program, level, m.text.c_str());
  }
}

bool save_at_end(MapStore& store, const Estimator& estimator, hal::TimeNs t_ns,
                 const char* program) {
  MapStore::Saved saved;
  std::string error;
  if (!store.save(estimator, t_ns, saved, error)) {
    std::fprintf(stderr, "%s: error: map: %s\n", program, error.c_str());
    return false;
  }
  print_saved(program, store, saved);
  return true;
}

RunMap::RunMap(const MapStoreOptions& options, const char* program) : program_(program) {
  if (options.path.empty()) {
    return;
  }
  store_.emplace(options);
  const MapStore::StartCheck check = store_->check_at_start();
  print_start_check(check, program_);
  refused_ = check.found == MapStore::Found::kLocked;
  if (!refused_) {
    saving_.emplace(*store_, program_);
  }
}

bool RunMap::finish(const Estimator& estimator, hal::TimeNs t_ns) {
  return !store_ || refused_ || save_at_end(*store_, estimator, t_ns, program_);
}

}  // namespace cleanslam::firmware
