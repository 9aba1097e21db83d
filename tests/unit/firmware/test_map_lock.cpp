// One writer per map file (map_lock.hpp), the temporaries of saves cut short, and a symbolic link
// at the map path (map_paths.hpp).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cleanslam/firmware/map_lock.hpp"
#include "cleanslam/firmware/map_paths.hpp"
#include "cleanslam/firmware/map_store.hpp"

namespace cleanslam {
namespace {

namespace fs = std::filesystem;
namespace mf = hal::map_file;
using firmware::MapLock;
using firmware::MapStore;

struct Dir {
  fs::path path;
  explicit Dir(const std::string& name)
      : path(fs::temp_directory_path() /
             ("cleanslam_lock_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Dir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  Dir(const Dir&) = delete;
  Dir& operator=(const Dir&) = delete;
  [[nodiscard]] std::string file(const std::string& name) const { return (path / name).string(); }
};

std::string text_of(const MapStore::StartCheck& c) {
  std::string s;
  for (const auto& m : c.messages) {
    s += (m.error ? "error: " : m.warning ? "warning: " : "") + m.text + "\n";
  }
  return s;
}

std::string pid_text() {
  return "pid " + std::to_string(::getpid());
}

firmware::MapStoreOptions store_options(const std::string& path) {
  firmware::MapStoreOptions o;
  o.path = path;
  return o;
}

// An estimator with a one-landmark map.
class OneLandmark final : public firmware::Estimator {
 public:
  void reset(hal::TimeNs /*t_ns*/) override {}
  void add_gyro(const hal::GyroSample& /*s*/) override {}
  void add_encoder(const hal::EncoderSample& /*s*/) override {}
  void predict(hal::TimeNs /*t_ns*/) override {}
  void begin_frame(const hal::CameraFrame& /*frame*/) override {}
  bool step_frame(int& /*budget*/) override { return true; }
  int update_records(const hal::log::UpdateRecord*& records) const override {
    records = nullptr;
    return 0;
  }
  [[nodiscard]] hal::PoseEstimate pose(hal::TimeNs t_ns) const override {
    hal::PoseEstimate p;
    p.t_ns = t_ns;
    return p;
  }
  [[nodiscard]] bool standing_still() const override { return false; }
  [[nodiscard]] hal::PoseEstimate dead_reckoning_pose(hal::TimeNs t_ns) const override {
    return pose(t_ns);
  }
  int landmarks(firmware::LandmarkEstimate* /*out*/, int /*max*/) const override { return 0; }
  bool map_snapshot(hal::TimeNs t_ns, mf::MapSnapshot& out) const override {
    out.saved_at_ns = t_ns;
    out.dock = {};
    out.count = 1;
    mf::MapLandmark& l = out.landmarks[0];
    l = mf::MapLandmark{};
    l.id = 7;
    l.position_m = {1.0, 2.0, 0.5};
    l.covariance = {0.01, 0.0, 0.0, 0.01, 0.0, 0.01};
    return true;
  }
};

bool save(MapStore& store, hal::TimeNs t, std::string& error) {
  const OneLandmark estimator;
  MapStore::Saved saved;
  return store.save(estimator, t, saved, error);
}

TEST(MapLock, ASecondHolderIsRefusedAndToldWhoHoldsIt) {
  Dir dir("lock");
  const std::string path = dir.file("map.bin.lock");
  std::string why;
  {
    MapLock first(path);
    ASSERT_EQ(first.acquire(why), MapLock::Result::kHeld) << why;
    EXPECT_TRUE(first.held());
    MapLock second(path);  // another open file description: flock refuses it as another process
    EXPECT_EQ(second.acquire(why), MapLock::Result::kBusy);
    EXPECT_FALSE(second.held());
    EXPECT_EQ(why.rfind(pid_text() + " ", 0), 0U) << why;
  }
  MapLock third(path);  // the first released its lock when it closed
  EXPECT_EQ(third.acquire(why), MapLock::Result::kHeld) << why;
}

TEST(MapLock, ALockFileThatCannotBeCreatedIsAnErrorNamingIt) {
  Dir dir("lockerr");
  const std::string path = dir.file("no/such/dir/map.bin.lock");
  MapLock lock(path);
  std::string why;
  EXPECT_EQ(lock.acquire(why), MapLock::Result::kError);
  EXPECT_EQ(why, path + ": cannot open the lock file: No such file or directory");
}

TEST(MapStoreLock, ASecondStoreOnOneMapIsRefusedAtStartAndSavesNothing) {
  Dir dir("second");
  const std::string path = dir.file("map.bin");
  MapStore first(store_options(path));
  ASSERT_EQ(first.check_at_start().found, MapStore::Found::kNone);
  std::string error;
  ASSERT_TRUE(save(first, 1, error)) << error;
  const auto before = fs::file_size(path);

  MapStore second(store_options(path));
  const MapStore::StartCheck c = second.check_at_start();
  EXPECT_EQ(c.found, MapStore::Found::kLocked) << text_of(c);
  EXPECT_NE(text_of(c).find("error: " + path + " is in use by another process (" + pid_text()),
            std::string::npos)
      << text_of(c);
  EXPECT_NE(text_of(c).find("holding " + path + ".lock"), std::string::npos) << text_of(c);
  EXPECT_NE(text_of(c).find("this run does not start"), std::string::npos) << text_of(c);
  EXPECT_FALSE(second.saving_allowed());
  EXPECT_FALSE(save(second, 2, error));
  EXPECT_EQ(error, path + ": not saved: another process holds " + path + ".lock");
  EXPECT_EQ(fs::file_size(path), before);
  EXPECT_TRUE(save(first, 3, error)) << error;
}

TEST(MapStoreLock, ASaveWithoutTheStartCheckTakesTheLockToo) {
  Dir dir("lazy");
  const std::string path = dir.file("map.bin");
  MapStore first(store_options(path));
  std::string error;
  ASSERT_TRUE(save(first, 1, error)) << error;
  MapStore second(store_options(path));
  EXPECT_FALSE(save(second, 2, error));
  EXPECT_NE(error.find("another process holds " + path + ".lock (" + pid_text()), std::string::npos)
      << error;
}

TEST(MapStoreLock, RunMapRefusesASecondRun) {
  Dir dir("runmap");
  const std::string path = dir.file("map.bin");
  firmware::RunMap first(store_options(path), "test");
  EXPECT_FALSE(first.refused());
  EXPECT_NE(first.task(), nullptr);
  firmware::RunMap second(store_options(path), "test");
  EXPECT_TRUE(second.refused());
  EXPECT_EQ(second.task(), nullptr);
}

// Temporaries of killed processes (any pid) and of earlier versions are removed under the lock;
// other files are not, and a process refused the lock removes nothing.
TEST(MapStoreLock, TemporariesOfSavesCutShortAreRemovedUnderTheLockOnly) {
  Dir dir("stale");
  const std::string path = dir.file("map.bin");
  const std::vector<std::string> stale{path + ".tmp", path + ".tmp.1", path + ".tmp.99999999"};
  const std::vector<std::string> kept{path + ".tmp.", path + ".tmp.12x", path + ".tmpx",
                                      dir.file("other.bin.tmp.5"), path + ".refused"};
  for (const std::string& f : stale) {
    std::ofstream(f) << "x";
  }
  for (const std::string& f : kept) {
    std::ofstream(f) << "x";
  }
  {
    MapLock other(path + ".lock");  // another process's, as far as flock is concerned
    std::string why;
    ASSERT_EQ(other.acquire(why), MapLock::Result::kHeld) << why;
    MapStore refused(store_options(path));
    EXPECT_EQ(refused.check_at_start().found, MapStore::Found::kLocked);
    for (const std::string& f : stale) {
      EXPECT_TRUE(fs::exists(f)) << f << " removed by a process without the lock";
    }
  }
  MapStore store(store_options(path));
  const MapStore::StartCheck c = store.check_at_start();
  EXPECT_EQ(c.found, MapStore::Found::kNone) << text_of(c);
  for (const std::string& f : stale) {
    EXPECT_FALSE(fs::exists(f)) << f;
    EXPECT_NE(text_of(c).find("removed " + f + ", a save cut short"), std::string::npos)
        << text_of(c);
  }
  for (const std::string& f : kept) {
    EXPECT_TRUE(fs::exists(f)) << f;
  }
}

TEST(MapPaths, TemporaryNames) {
  EXPECT_TRUE(firmware::is_map_temporary("map.bin.tmp", "map.bin"));
  EXPECT_TRUE(firmware::is_map_temporary("map.bin.tmp.123", "map.bin"));
  EXPECT_FALSE(firmware::is_map_temporary("map.bin.tmp.", "map.bin"));
  EXPECT_FALSE(firmware::is_map_temporary("map.bin.tmp.1a", "map.bin"));
  EXPECT_FALSE(firmware::is_map_temporary("map.bin.tmpa", "map.bin"));
  EXPECT_FALSE(firmware::is_map_temporary("map.bin", "map.bin"));
  EXPECT_FALSE(firmware::is_map_temporary("xmap.bin.tmp.1", "map.bin"));
  const firmware::MapPaths p = firmware::map_paths("maps/map.bin", 42);
  EXPECT_EQ(p.file, "maps/map.bin");
  EXPECT_EQ(p.dir, "maps");
  EXPECT_EQ(p.tmp, "maps/map.bin.tmp.42");
  EXPECT_EQ(p.lock, "maps/map.bin.lock");
  EXPECT_EQ(p.refused, "maps/map.bin.refused");
  EXPECT_FALSE(p.symlink());
  EXPECT_EQ(firmware::map_paths("map.bin", 1).dir, ".");
}

// A link at the map path: the map is saved to its target, atomically in the target's directory,
// and the link stays a link (it used to be replaced by a regular file at the first save).
TEST(MapPaths, ASymlinkedMapIsSavedThroughToItsTarget) {
  Dir dir("symlink");
  fs::create_directories(dir.path / "store");
  const std::string target = dir.file("store/real.bin");
  const std::string link = dir.file("map.bin");
  fs::create_symlink("store/real.bin", link);  // relative: against the link's directory
  {
    MapStore store(store_options(link));
    const MapStore::StartCheck c = store.check_at_start();
    EXPECT_EQ(c.found, MapStore::Found::kNone) << text_of(c);
    EXPECT_NE(text_of(c).find(link + " is a symbolic link to " + target +
                              ", which does not exist yet: the map is read from and saved to " +
                              target + ", and the link is kept"),
              std::string::npos)
        << text_of(c);
    std::string error;
    ASSERT_TRUE(save(store, 5, error)) << error;
    EXPECT_EQ(store.paths().tmp, target + ".tmp." + std::to_string(::getpid()));
  }
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(target)));
  EXPECT_EQ(fs::file_size(target), mf::file_size(1));
  EXPECT_TRUE(fs::exists(target + ".lock"));
  EXPECT_FALSE(fs::exists(link + ".lock"));
  MapStore again(store_options(link));
  const MapStore::StartCheck c = again.check_at_start();
  EXPECT_EQ(c.found, MapStore::Found::kValid) << text_of(c);
  EXPECT_EQ(again.snapshot().count, 1);
  // Two links to one target share its lock.
  const std::string link2 = dir.file("map2.bin");
  fs::create_symlink(target, link2);
  MapStore second(store_options(link2));
  EXPECT_EQ(second.check_at_start().found, MapStore::Found::kLocked);
}

TEST(MapPaths, AChainOfLinksIsFollowedAndALoopRefusedNamingIt) {
  Dir dir("chain");
  const std::string target = dir.file("real.bin");
  fs::create_symlink(target, dir.file("b"));
  fs::create_symlink(dir.file("b"), dir.file("a"));
  EXPECT_EQ(firmware::map_paths(dir.file("a"), 1).file, target);
  fs::create_symlink(dir.file("loop2"), dir.file("loop1"));
  fs::create_symlink(dir.file("loop1"), dir.file("loop2"));
  MapStore store(store_options(dir.file("loop1")));
  const MapStore::StartCheck c = store.check_at_start();
  EXPECT_EQ(c.found, MapStore::Found::kUnreadable);
  EXPECT_NE(
      text_of(c).find(dir.file("loop1") + ": more than 40 symbolic links (a loop?): it is "
                                          "kept as it is, and this run does not save its map"),
      std::string::npos)
      << text_of(c);
  std::string error;
  EXPECT_FALSE(save(store, 1, error));
  EXPECT_TRUE(fs::is_symlink(dir.file("loop1")));
}

}  // namespace
}  // namespace cleanslam
