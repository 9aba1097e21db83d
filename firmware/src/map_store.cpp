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
  std::fprintf(stderr, "%s: map: saved %d landmarks to %s (%zu KB)\n", program, saved.landmarks,
               store.path().c_str(), (saved.bytes + 512) / 1024);
}

}  // namespace

MapStore::MapStore(MapStoreOptions options)
    : options_(std::move(options)),
      tmp_path_(options_.path + ".tmp"),
      refused_path_(options_.path + ".refused"),
      interval_ns_(hal::from_seconds(options_.save_interval_s)),
      snapshot_(std::make_unique<mf::MapSnapshot>()),
      buffer_(mf::kMaxFileSize + 1) {
  const std::filesystem::path parent = std::filesystem::path(options_.path).parent_path();
  dir_ = parent.empty() ? std::string(".") : parent.string();
}

void MapStore::refuse(StartCheck& c, const std::string& reason) {
  c.found = Found::kRefused;
  struct stat st {};
  const bool older = ::lstat(refused_path_.c_str(), &st) == 0;
  if (std::rename(options_.path.c_str(), refused_path_.c_str()) != 0) {
    const int e = errno;
    c.found = Found::kUnreadable;
    saving_allowed_ = false;
    c.messages.push_back({true, options_.path + ": refused: " + reason +
                                    "; it could not be moved to " + refused_path_ + ": " +
                                    errno_text(e) +
                                    ": it is kept as it is, and this run does not save its map"});
    return;
  }
  c.messages.push_back({true, options_.path + ": refused: " + reason + "; moved to " +
                                  refused_path_ + (older ? " (replacing an older one)" : "") +
                                  ": a new map starts"});
}

MapStore::StartCheck MapStore::check_at_start() {
  StartCheck c;
  snapshot_->count = 0;
  struct stat st {};
  if (::lstat(tmp_path_.c_str(), &st) == 0) {
    if (::unlink(tmp_path_.c_str()) == 0) {
      c.messages.push_back({false, "removed " + tmp_path_ +
                                       ", a save cut short (power cut or crash); the map saved "
                                       "before it is " +
                                       options_.path});
    } else {
      c.messages.push_back(
          {true, tmp_path_ + ": a save cut short, could not be removed: " + errno_text(errno)});
    }
  }
  const int fd =
      ::open(options_.path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);  // a FIFO must not block
  if (fd < 0) {
    const int e = errno;
    if (e == ENOENT) {
      c.messages.push_back({false, "no saved map at " + options_.path + ": a new map"});
      if (::access(dir_.c_str(), W_OK | X_OK) != 0) {
        c.messages.push_back({true, dir_ + ": " + errno_text(errno) +
                                        ": the map cannot be saved to " + options_.path});
      }
      return c;
    }
    c.found = Found::kUnreadable;
    saving_allowed_ = false;
    c.messages.push_back({true, options_.path + ": cannot open: " + errno_text(e) +
                                    ": it is kept as it is, and this run does not save its map"});
    return c;
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
    c.messages.push_back({true, options_.path + ": " + unreadable +
                                    ": it is kept as it is, and this run does not save its map"});
    return c;
  }
  if (n < 0 || static_cast<std::size_t>(n) > mf::kMaxFileSize) {
    c.decoded.refusal = mf::Refusal::kSize;
    c.decoded.offset = mf::kMaxFileSize;
    refuse(c, std::to_string(st.st_size) + " bytes, more than a map file holds (" +
                  std::to_string(mf::kMaxFileSize) + ")");
    return c;
  }
  c.decoded = mf::decode(buffer_.data(), static_cast<std::size_t>(n), *snapshot_);
  if (c.decoded.refusal != mf::Refusal::kNone) {
    refuse(c, std::string(mf::to_string(c.decoded.refusal)) + " at byte " +
                  std::to_string(c.decoded.offset));
    return c;
  }
  c.found = Found::kValid;
  char when[64];
  std::snprintf(when, sizeof when, "%.1f", hal::to_seconds(snapshot_->saved_at_ns));
  c.messages.push_back({false, options_.path + ": a saved map of " +
                                   std::to_string(snapshot_->count) +
                                   " landmarks, saved at t=" + when + " s"});
  c.messages.push_back({false,
                        "starting from a saved map is not built yet: this run makes a new map, "
                        "which replaces " +
                            options_.path + " at its first save"});
  return c;
}

bool MapStore::save(const Estimator& estimator, hal::TimeNs t_ns, Saved& saved,
                    std::string& error) {
  if (!saving_allowed_) {
    error = options_.path + ": not saved: the file found at start is kept as it is";
    return false;
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
  const int fd = ::open(tmp_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    error = tmp_path_ + ": cannot create: " + errno_text(errno) + "; " + options_.path +
            " is unchanged";
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
  if (failed == nullptr && std::rename(tmp_path_.c_str(), options_.path.c_str()) != 0) {
    e = errno;
    ::unlink(tmp_path_.c_str());
    error = tmp_path_ + ": cannot rename onto " + options_.path + ": " + errno_text(e) + "; " +
            options_.path + " is unchanged";
    return false;
  }
  if (failed != nullptr) {
    ::unlink(tmp_path_.c_str());
    error =
        tmp_path_ + ": " + failed + ": " + errno_text(e) + "; " + options_.path + " is unchanged";
    return false;
  }
  const int dir = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir < 0 || ::fsync(dir) != 0) {
    e = errno;
    if (dir >= 0) {
      ::close(dir);
    }
    error = dir_ + ": cannot sync the directory: " + errno_text(e) + "; " + options_.path +
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
    std::fprintf(stderr, "%s: %smap: %s\n", program, m.warning ? "warning: " : "", m.text.c_str());
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
  print_start_check(store_->check_at_start(), program_);
  saving_.emplace(*store_, program_);
}

bool RunMap::finish(const Estimator& estimator, hal::TimeNs t_ns) {
  return !store_ || save_at_end(*store_, estimator, t_ns, program_);
}

}  // namespace cleanslam::firmware
