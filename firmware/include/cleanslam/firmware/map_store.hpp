#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cleanslam/firmware/estimator.hpp"
#include "cleanslam/firmware/map_lock.hpp"
#include "cleanslam/firmware/map_paths.hpp"
#include "cleanslam/firmware/run.hpp"
#include "cleanslam/hal/map_file.hpp"
#include "cleanslam/hal/time.hpp"

namespace cleanslam::firmware {

struct MapStoreOptions {
  std::string path;                // the map file (hal/map_file.hpp); "": none
  double save_interval_s = 300.0;  // saved this often while running, and at the end of a run
};

// The map file kept across cleaning runs. One process writes it: the check at start takes an
// advisory lock on `<path>.lock` (map_lock.hpp) and a second process is refused (Found::kLocked).
// Saving is atomic: the bytes go to this process's `<path>.tmp.<pid>` in the same directory, which
// is synced, renamed onto `<path>`, and the directory synced; a save cut short leaves the previous
// map whole. At start-up, under the lock, temporary files left by saves cut short are removed and
// `<path>` is checked; a file the decoder refuses is moved aside to `<path>.refused`, never
// overwritten. A symbolic link at `<path>` is followed, and all of this happens beside its target
// (map_paths.hpp). The snapshot and the file buffer are allocated once, in the constructor; a save
// allocates nothing unless it fails.
class MapStore {
 public:
  enum class Found {
    kNone,        // no file: a new map
    kValid,       // a map the decoder accepts, in snapshot()
    kRefused,     // refused and moved aside to `<path>.refused`
    kUnreadable,  // could not be read or moved aside: kept as it is, and this run saves nothing
    kLocked,      // another process holds the map's lock: this run must not start
  };
  struct Message {
    bool warning = false;
    std::string text;  // names the file
    bool error = false;
  };
  struct StartCheck {
    Found found = Found::kNone;
    hal::map_file::Decoded decoded;
    std::vector<Message> messages;
  };
  struct Saved {
    int landmarks = 0;
    std::size_t bytes = 0;
  };

  explicit MapStore(MapStoreOptions options);

  // What `<path>` holds; the map found stays in snapshot() until the first save.
  StartCheck check_at_start();
  // The estimator's map, written atomically. On failure `error` names the file and the reason,
  // and the map saved before is untouched.
  bool save(const Estimator& estimator, hal::TimeNs t_ns, Saved& saved, std::string& error);
  // True once every save interval, counted from the first call.
  [[nodiscard]] bool due(hal::TimeNs t_ns);
  // False when the file found at start could be neither read nor moved aside.
  [[nodiscard]] bool saving_allowed() const { return saving_allowed_; }
  [[nodiscard]] const hal::map_file::MapSnapshot& snapshot() const { return *snapshot_; }
  [[nodiscard]] const std::string& path() const { return options_.path; }
  // The files the path names: the map itself (a symbolic link's target), its temporary and lock.
  [[nodiscard]] const MapPaths& paths() const { return paths_; }

 private:
  void refuse(StartCheck& c, const std::string& reason);
  // Takes the lock (a second process: kLocked and an error message); true unless refused.
  bool lock(StartCheck& c);
  void remove_stale_temporaries(StartCheck& c);
  // The check of `<file>` itself, after the lock.
  void check_file(StartCheck& c);

  MapStoreOptions options_;
  MapPaths paths_;
  MapLock lock_;
  bool lock_tried_ = false;
  bool locked_out_ = false;  // another process held the lock
  hal::TimeNs interval_ns_ = 0;
  hal::TimeNs next_due_ns_ = -1;
  bool saving_allowed_ = true;
  std::unique_ptr<hal::map_file::MapSnapshot> snapshot_;
  std::vector<std::uint8_t> buffer_;
};

// Saves the map every map.save_interval_s from a runner (run.hpp), and tells on stderr as
// "<program>: map: saved N landmarks to PATH (K KB)".
class PeriodicMapSave final : public LiveTask {
 public:
  PeriodicMapSave(MapStore& store, const char* program) : store_(store), program_(program) {}
  void run(const Loop& loop, hal::TimeNs now) override;
  [[nodiscard]] hal::TimeNs next_due_ns() const override { return -1; }

 private:
  MapStore& store_;
  const char* program_;
};

// Prints check_at_start()'s messages as "<program>: map: ..." (warnings marked).
void print_start_check(const MapStore::StartCheck& check, const char* program);
// Saves at the end of a run and tells; false (the error printed) when the save failed.
bool save_at_end(MapStore& store, const Estimator& estimator, hal::TimeNs t_ns,
                 const char* program);

// The map a run keeps when map.path names a file: checked (and told) at construction, saved by
// task() every save interval and by finish() at the end. With no path, nothing.
class RunMap {
 public:
  RunMap(const MapStoreOptions& options, const char* program);
  RunMap(const RunMap&) = delete;
  RunMap& operator=(const RunMap&) = delete;
  // The periodic save for a runner (run.hpp), or null.
  [[nodiscard]] LiveTask* task() { return saving_ ? &*saving_ : nullptr; }
  // True when another process holds the map (told): the run must not start.
  [[nodiscard]] bool refused() const { return refused_; }
  // The save at the end of the run; false (told) when it failed.
  bool finish(const Estimator& estimator, hal::TimeNs t_ns);

 private:
  const char* program_;
  bool refused_ = false;
  std::optional<MapStore> store_;
  std::optional<PeriodicMapSave> saving_;
};

}  // namespace cleanslam::firmware
