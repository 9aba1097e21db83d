#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "cleanslam/firmware/config.hpp"
#include "cleanslam/firmware/map_store.hpp"
#include "cleanslam/firmware/program.hpp"
#include "cleanslam/firmware/run.hpp"
#include "cleanslam/readers/dataset_source.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"

namespace cleanslam {
namespace {

namespace fs = std::filesystem;
namespace mf = hal::map_file;
using firmware::MapStore;
using firmware::MapStoreOptions;

struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name)
      : path(fs::temp_directory_path() /
             ("cleanslam_map_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::permissions(path, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] std::string file(const std::string& name) const { return (path / name).string(); }
};

std::vector<std::uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::uint8_t* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

std::string all_text(const MapStore::StartCheck& c) {
  std::string s;
  for (const auto& m : c.messages) {
    s += m.text + "\n";
  }
  return s;
}

// An estimator whose map is a given snapshot; nothing else.
class SnapshotEstimator final : public firmware::Estimator {
 public:
  mf::MapSnapshot map{};
  bool keeps_map = true;

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
    if (!keeps_map) {
      return false;
    }
    out = map;
    out.saved_at_ns = t_ns;
    return true;
  }
};

// Three landmarks with distinct values and patches.
void fill_map(mf::MapSnapshot& m, double shift) {
  m.count = 3;
  m.dock = {0.5 + shift, -0.25, 0.125};
  for (int i = 0; i < m.count; ++i) {
    mf::MapLandmark& l = m.landmarks[static_cast<std::size_t>(i)];
    const double k = i + shift;
    l.id = 100 + i;
    l.flags = i == 0 ? 0U : (mf::kHasPatch | (i == 2 ? mf::kHasAnchor : 0U));
    l.position_m = {1.0 + k, -2.0 * k, 0.3 + 0.01 * k};
    l.covariance = {0.04 + 0.001 * k, 0.001, 0.0, 0.05, -0.002, 0.09};
    l.first_depth_m = i == 0 ? 0.0 : 1.5 + k;
    l.anchor_m = i == 2 ? std::array<double, 3>{0.1, 0.2, 0.08} : std::array<double, 3>{};
    for (std::size_t p = 0; p < l.patch.size(); ++p) {
      l.patch[p] = i == 0 ? 0.0F : static_cast<float>((p * 7 + static_cast<std::size_t>(i)) % 251);
    }
  }
}

// This process's temporary file for a map path (map_paths.hpp).
std::string tmp_of(const std::string& path) {
  return path + ".tmp." + std::to_string(::getpid());
}

MapStoreOptions options(const std::string& path) {
  MapStoreOptions o;
  o.path = path;
  o.save_interval_s = 300.0;
  return o;
}

TEST(MapStore, SaveThenStartUpCheckGivesTheSameMap) {
  TempDir dir("roundtrip");
  const std::string path = dir.file("map.bin");
  SnapshotEstimator estimator;
  fill_map(estimator.map, 0.0);
  {
    MapStore store(options(path));
    const MapStore::StartCheck first = store.check_at_start();
    EXPECT_EQ(first.found, MapStore::Found::kNone);
    EXPECT_NE(all_text(first).find("no saved map at " + path + ": a new map"), std::string::npos)
        << all_text(first);
    MapStore::Saved saved;
    std::string error;
    ASSERT_TRUE(store.save(estimator, 42 * hal::kNsPerSecond, saved, error)) << error;
    EXPECT_EQ(saved.landmarks, 3);
    EXPECT_EQ(saved.bytes, mf::file_size(3));
    EXPECT_EQ(fs::file_size(path), mf::file_size(3));
    EXPECT_FALSE(fs::exists(tmp_of(path)));
  }
  MapStore store(options(path));
  const MapStore::StartCheck c = store.check_at_start();
  ASSERT_EQ(c.found, MapStore::Found::kValid) << all_text(c);
  EXPECT_EQ(c.decoded.count, 3U);
  EXPECT_NE(all_text(c).find(path + ": a saved map of 3 landmarks, saved at t=42.0 s"),
            std::string::npos)
      << all_text(c);
  EXPECT_NE(all_text(c).find("not built yet: this run makes a new map"), std::string::npos);
  const mf::MapSnapshot& m = store.snapshot();
  ASSERT_EQ(m.count, 3);
  EXPECT_EQ(m.saved_at_ns, 42 * hal::kNsPerSecond);
  EXPECT_EQ(m.dock.x_m, estimator.map.dock.x_m);
  EXPECT_EQ(m.dock.yaw_rad, estimator.map.dock.yaw_rad);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(m.landmarks[i] == estimator.map.landmarks[i]) << "landmark " << i;
  }
}

TEST(MapStore, ASecondSaveReplacesTheFirstWhole) {
  TempDir dir("replace");
  const std::string path = dir.file("map.bin");
  SnapshotEstimator estimator;
  fill_map(estimator.map, 0.0);
  {
    MapStore store(options(path));
    MapStore::Saved saved;
    std::string error;
    ASSERT_TRUE(store.save(estimator, 1, saved, error)) << error;
    fill_map(estimator.map, 5.0);
    estimator.map.count = 2;
    ASSERT_TRUE(store.save(estimator, 2, saved, error)) << error;
    EXPECT_EQ(saved.landmarks, 2);
  }  // its lock released, as at the end of a run
  MapStore again(options(path));
  ASSERT_EQ(again.check_at_start().found, MapStore::Found::kValid);
  EXPECT_EQ(again.snapshot().count, 2);
  EXPECT_EQ(again.snapshot().landmarks[1].position_m, estimator.map.landmarks[1].position_m);
}

TEST(MapStore, APeriodicSaveAllocatesNothing) {
  TempDir dir("alloc");
  SnapshotEstimator estimator;
  fill_map(estimator.map, 0.0);
  MapStoreOptions o = options(dir.file("map.bin"));
  o.save_interval_s = 1.0;
  std::size_t allocations = 0;
  {
    MapStore store(o);
    firmware::Loop loop(firmware::LoopOptions{}, estimator);
    firmware::PeriodicMapSave saving(store, "test");
    saving.run(loop, 0);
    test::AllocationScope scope;
    saving.run(loop, hal::kNsPerSecond);  // the first save also takes the lock
    allocations = scope.count();
  }
  EXPECT_EQ(allocations, 0U);
  MapStore again(options(dir.file("map.bin")));
  EXPECT_EQ(again.check_at_start().found, MapStore::Found::kValid);
}

TEST(MapStore, SaveIsDueOnceEveryInterval) {
  MapStoreOptions o = options("/nonexistent/map.bin");
  o.save_interval_s = 10.0;
  MapStore store(o);
  const hal::TimeNs s = hal::kNsPerSecond;
  EXPECT_FALSE(store.due(100 * s));  // the first call starts the count
  EXPECT_FALSE(store.due(109 * s));
  EXPECT_TRUE(store.due(110 * s));
  EXPECT_FALSE(store.due(111 * s));
  EXPECT_FALSE(store.due(119 * s));
  EXPECT_TRUE(store.due(125 * s));
  EXPECT_FALSE(store.due(134 * s));
  EXPECT_TRUE(store.due(135 * s));
}

TEST(MapStore, ASaveIntoAMissingDirectoryFailsNamingThePath) {
  TempDir dir("missing");
  SnapshotEstimator estimator;
  fill_map(estimator.map, 0.0);
  const std::string path = dir.file("no/such/dir/map.bin");
  MapStore store(options(path));
  const MapStore::StartCheck c = store.check_at_start();
  EXPECT_EQ(c.found, MapStore::Found::kNone);
  EXPECT_NE(all_text(c).find("the map cannot be saved to " + path), std::string::npos)
      << all_text(c);
  MapStore::Saved saved;
  std::string error;
  EXPECT_FALSE(store.save(estimator, 1, saved, error));
  EXPECT_NE(error.find(tmp_of(path) + ": cannot create: No such file or directory"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find(path + " is unchanged"), std::string::npos) << error;
  EXPECT_FALSE(fs::exists(dir.file("no")));
}

// A saved map, then a save that fails: the map saved before is untouched.
struct SavedBefore {
  TempDir dir;
  std::string path;
  SnapshotEstimator estimator;
  std::vector<std::uint8_t> before;
  explicit SavedBefore(const std::string& name) : dir(name), path(dir.file("map.bin")) {
    fill_map(estimator.map, 0.0);
    MapStore store(options(path));
    MapStore::Saved saved;
    std::string error;
    EXPECT_TRUE(store.save(estimator, 1, saved, error)) << error;
    before = read_bytes(path);
    fill_map(estimator.map, 3.0);
  }
};

TEST(MapStore, ASaveIntoAReadOnlyDirectoryFailsAndKeepsTheOldMap) {
  SavedBefore s("readonly");
  ::chmod(s.dir.path.c_str(), 0500);
  if (::access(s.dir.path.c_str(), W_OK) == 0) {
    ::chmod(s.dir.path.c_str(), 0700);
    GTEST_SKIP() << "running with privileges that write into a read-only directory";
  }
  MapStore store(options(s.path));
  MapStore::Saved saved;
  std::string error;
  const bool ok = store.save(s.estimator, 2, saved, error);
  ::chmod(s.dir.path.c_str(), 0700);
  EXPECT_FALSE(ok);
  EXPECT_NE(error.find(tmp_of(s.path) + ": cannot create: Permission denied"), std::string::npos)
      << error;
  EXPECT_EQ(read_bytes(s.path), s.before);
  EXPECT_FALSE(fs::exists(tmp_of(s.path)));
}

TEST(MapStore, ATemporaryFileThatCannotBeCreatedKeepsTheOldMap) {
  SavedBefore s("tmpdir");
  fs::create_directories(tmp_of(s.path));  // even root cannot open a directory for writing
  MapStore store(options(s.path));
  MapStore::Saved saved;
  std::string error;
  EXPECT_FALSE(store.save(s.estimator, 2, saved, error));
  EXPECT_NE(error.find(tmp_of(s.path) + ": cannot create: Is a directory"), std::string::npos)
      << error;
  EXPECT_EQ(read_bytes(s.path), s.before);
}

TEST(MapStore, ARenameThatFailsRemovesTheTemporaryFile) {
  TempDir dir("rename");
  const std::string path = dir.file("map.bin");
  fs::create_directories(path + "/occupied");  // a non-empty directory cannot be replaced
  SnapshotEstimator estimator;
  fill_map(estimator.map, 0.0);
  MapStore store(options(path));
  MapStore::Saved saved;
  std::string error;
  EXPECT_FALSE(store.save(estimator, 2, saved, error));
  EXPECT_NE(error.find(tmp_of(path) + ": cannot rename onto " + path + ": "), std::string::npos)
      << error;
  EXPECT_FALSE(fs::exists(tmp_of(path)));
  EXPECT_TRUE(fs::is_directory(path + "/occupied"));
}

TEST(MapStore, AnEstimatorWithoutAMapSavesNothing) {
  TempDir dir("nomap");
  const std::string path = dir.file("map.bin");
  SnapshotEstimator estimator;
  estimator.keeps_map = false;
  MapStore store(options(path));
  MapStore::Saved saved;
  std::string error;
  EXPECT_FALSE(store.save(estimator, 1, saved, error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_FALSE(fs::exists(path));
}

TEST(MapStore, AFileLargerThanAMapIsRefusedUnreadAndMovedAside) {
  TempDir dir("large");
  const std::string path = dir.file("map.bin");
  { std::ofstream create(path); }
  fs::resize_file(path, mf::kMaxFileSize + 1);
  MapStore store(options(path));
  const MapStore::StartCheck c = store.check_at_start();
  EXPECT_EQ(c.found, MapStore::Found::kRefused) << all_text(c);
  EXPECT_NE(all_text(c).find("more than a map file holds"), std::string::npos) << all_text(c);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(fs::file_size(path + ".refused"), mf::kMaxFileSize + 1);
}

TEST(MapStore, AMapThatCannotBeReadIsKeptAndNotOverwritten) {
  TempDir dir("unreadable");
  const std::string path = dir.file("map.bin");
  fs::create_directories(path);  // a directory where the map should be
  MapStore store(options(path));
  const MapStore::StartCheck c = store.check_at_start();
  EXPECT_EQ(c.found, MapStore::Found::kUnreadable) << all_text(c);
  EXPECT_NE(all_text(c).find(path + ": not a regular file"), std::string::npos) << all_text(c);
  EXPECT_FALSE(store.saving_allowed());
  SnapshotEstimator estimator;
  fill_map(estimator.map, 0.0);
  MapStore::Saved saved;
  std::string error;
  EXPECT_FALSE(store.save(estimator, 1, saved, error));
  EXPECT_TRUE(fs::is_directory(path));
}

TEST(MapConfig, KeysParseRoundTripAndAreRangeChecked) {
  EXPECT_EQ(firmware::FirmwareConfig{}.map.path, "");
  EXPECT_EQ(firmware::FirmwareConfig{}.map.save_interval_s, 300.0);
  const firmware::ConfigResult r = firmware::parse_config(
      "map:\n  path: \"/var/lib/cleanslam/map.bin\"\n  save_interval_s: 60\n", "m.yaml", {});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.config.map.path, "/var/lib/cleanslam/map.bin");
  EXPECT_EQ(r.config.map.save_interval_s, 60.0);
  const std::string text = firmware::config_text(r.config);
  const firmware::ConfigResult back = firmware::parse_config(text, "back.yaml", {});
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back.config.map.path, r.config.map.path);
  EXPECT_EQ(back.config.map.save_interval_s, 60.0);
  EXPECT_EQ(firmware::config_text(back.config), text);
  for (const char* bad :
       {"map.save_interval_s=0", "map.save_interval_s=-5", "map.save_interval_s=1e9"}) {
    const firmware::ConfigResult b = firmware::parse_config("", "m.yaml", {bad});
    ASSERT_EQ(b.errors.size(), 1U) << bad;
    EXPECT_NE(b.errors[0].find("map.save_interval_s"), std::string::npos) << b.errors[0];
    EXPECT_NE(b.errors[0].find("out of range"), std::string::npos) << b.errors[0];
  }
  const firmware::ConfigResult unknown = firmware::parse_config("map:\n  paht: x\n", "u.yaml", {});
  ASSERT_EQ(unknown.errors.size(), 1U);
  EXPECT_NE(unknown.errors[0].find("u.yaml:2"), std::string::npos) << unknown.errors[0];
  EXPECT_NE(unknown.errors[0].find("map.paht"), std::string::npos) << unknown.errors[0];
}

TEST(MapStore, AFifoWhereTheMapShouldBeDoesNotHoldUpTheStart) {
  TempDir dir("fifo");
  const std::string path = dir.file("map.bin");
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  MapStore store(options(path));
  const MapStore::StartCheck c = store.check_at_start();
  EXPECT_EQ(c.found, MapStore::Found::kUnreadable) << all_text(c);
  EXPECT_NE(all_text(c).find(path + ": not a regular file"), std::string::npos) << all_text(c);
}

// A short simulated run through `cleanslam --dataset` with map.path set (and recorded), and the
// same run in-process for the landmarks it ends with.
struct RealRun {
  bool ok = false;
  std::string why;
  TempDir dir{"real"};
  std::string map_path;
  std::string log_path;
  std::vector<std::uint8_t> map_bytes;
  int program_status = -1;
  std::vector<firmware::LandmarkEstimate> landmarks;
  hal::TimeNs first_ns = 0;
  hal::TimeNs end_ns = 0;
  std::vector<std::uint8_t> periodic_bytes;  // the in-process run's last periodic save

  RealRun() {
    const std::string dataset = dir.file("dataset");
    auto scenario = sim_hal::sim::load_scenario("default-room", {"duration_s=25"});
    if (!scenario.ok() || !sim_hal::sim::simulate(*scenario, dataset).ok()) {
      why = "the simulator failed";
      return;
    }
    map_path = dir.file("map.bin");
    log_path = dir.file("run.log");
    const std::vector<std::string> sets{"map.path=\"" + map_path + "\"", "map.save_interval_s=5"};
    std::vector<std::string> args{"cleanslam", "--dataset", dataset, "--record", log_path};
    for (const std::string& s : sets) {
      args.emplace_back("--set");
      args.push_back(s);
    }
    std::vector<char*> argv;
    argv.reserve(args.size());
    for (std::string& a : args) {
      argv.push_back(a.data());
    }
    program_status = firmware::program_main(static_cast<int>(argv.size()), argv.data());
    map_bytes = read_bytes(map_path);

    const firmware::ConfigResult cfg =
        firmware::load_config("", {"source.kind=dataset", "source.path=\"" + dataset + "\""});
    if (!cfg.ok()) {
      why = "configuration";
      return;
    }
    firmware::FirmwareConfig config = cfg.config;
    readers::DatasetSource::Options source_options;
    source_options.load.max_span_ns = config.loop.max_span_ns;
    auto source = readers::DatasetSource::open(dataset, source_options);
    if (!source.ok()) {
      why = source.error();
      return;
    }
    config.calibration = source->calibration();
    const auto estimator = firmware::make_estimator(config);
    firmware::Loop loop(firmware::loop_options(config), *estimator);
    loop.add_source(&source.value());
    first_ns = source->summary().first_ns;
    MapStoreOptions periodic;
    periodic.path = dir.file("periodic.bin");
    periodic.save_interval_s = 7.0;
    MapStore store(periodic);
    firmware::PeriodicMapSave saving(store, "test");
    firmware::VirtualClock clock;
    firmware::run_virtual(loop, clock, false, nullptr, &saving);
    end_ns = clock.now();
    periodic_bytes = read_bytes(periodic.path);
    landmarks.resize(hal::kMaxLandmarks);
    landmarks.resize(static_cast<std::size_t>(
        estimator->landmarks(landmarks.data(), static_cast<int>(landmarks.size()))));
    ok = true;
  }
};

const RealRun& real_run() {
  static const RealRun run;
  return run;
}

TEST(MapStoreFirmware, ARunSavesTheMapItEndsWithAndAReplayWritesNone) {
  const RealRun& run = real_run();
  ASSERT_TRUE(run.ok) << run.why;
  EXPECT_EQ(run.program_status, 0);
  ASSERT_FALSE(run.map_bytes.empty()) << run.map_path << " not written";
  EXPECT_FALSE(fs::exists(run.map_path + ".tmp"));
  EXPECT_FALSE(fs::exists(tmp_of(run.map_path)));
  auto m = std::make_unique<mf::MapSnapshot>();
  const mf::Decoded d = mf::decode(run.map_bytes.data(), run.map_bytes.size(), *m);
  ASSERT_EQ(d.refusal, mf::Refusal::kNone) << mf::to_string(d.refusal) << " at " << d.offset;
  ASSERT_GT(run.landmarks.size(), 3U) << "a run that maps nothing tests nothing";
  ASSERT_EQ(m->count, static_cast<int>(run.landmarks.size()));
  EXPECT_EQ(m->saved_at_ns, run.end_ns) << "not the map of the run's end";
  for (std::size_t i = 0; i < run.landmarks.size(); ++i) {
    EXPECT_EQ(m->landmarks[i].position_m, run.landmarks[i].position_m) << "landmark " << i;
    EXPECT_EQ(m->landmarks[i].covariance[0], run.landmarks[i].covariance[0]) << "landmark " << i;
  }

  // The recorded run replays bit for bit, and the replay leaves the map alone.
  const std::vector<std::uint8_t> before = read_bytes(run.map_path);
  fs::remove(run.map_path);
  std::string replay = "--replay";
  std::string log = run.log_path;
  std::string out = "--replay-out";
  std::string out_path = run.log_path + ".replay";
  std::string name = "cleanslam";
  std::array<char*, 5> argv{name.data(), replay.data(), log.data(), out.data(), out_path.data()};
  EXPECT_EQ(firmware::program_main(static_cast<int>(argv.size()), argv.data()), 0);
  EXPECT_FALSE(fs::exists(run.map_path)) << "--replay wrote a map";
  write_bytes(run.map_path, before.data(), before.size());
}

TEST(MapStoreFirmware, TheRunnerSavesPeriodically) {
  const RealRun& run = real_run();
  ASSERT_TRUE(run.ok) << run.why;
  auto m = std::make_unique<mf::MapSnapshot>();
  const mf::Decoded d = mf::decode(run.periodic_bytes.data(), run.periodic_bytes.size(), *m);
  ASSERT_EQ(d.refusal, mf::Refusal::kNone) << mf::to_string(d.refusal) << " at " << d.offset;
  // Every 7 s of a 25 s run: the last at 21 s.
  EXPECT_GE(m->saved_at_ns - run.first_ns, 21 * hal::kNsPerSecond);
  EXPECT_LT(m->saved_at_ns - run.first_ns, 22 * hal::kNsPerSecond);
  EXPECT_GT(m->count, 3);
}

// A save cut short at byte k leaves `<path>.tmp.<pid>` (`<path>.tmp` from an earlier version) with
// k bytes beside the previous map: the check at start keeps the previous map and removes the
// remnant.
TEST(MapStoreFirmware, APowerCutDuringASaveKeepsThePreviousMap) {
  const RealRun& run = real_run();
  ASSERT_TRUE(run.ok) << run.why;
  ASSERT_FALSE(run.map_bytes.empty());
  const std::vector<std::uint8_t>& bytes = run.map_bytes;
  TempDir dir("cut_tmp");
  const std::string path = dir.file("map.bin");
  write_bytes(path, bytes.data(), bytes.size());
  int checked = 0;
  for (std::size_t k = 0; k < bytes.size(); k += 64) {
    const std::string remnant = path + (k % 128 == 0 ? ".tmp" : ".tmp.4242");
    write_bytes(remnant, bytes.data(), k);
    MapStore store(options(path));
    const MapStore::StartCheck c = store.check_at_start();
    ASSERT_EQ(c.found, MapStore::Found::kValid) << "cut at " << k << ": " << all_text(c);
    ASSERT_NE(all_text(c).find("removed " + remnant + ", a save cut short"), std::string::npos)
        << all_text(c);
    ASSERT_FALSE(fs::exists(remnant)) << "cut at " << k;
    ASSERT_EQ(store.snapshot().count, static_cast<int>(run.landmarks.size()));
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

// The final file itself cut at byte k (a file system that lost its tail): refused, moved aside,
// a new map; never accepted.
TEST(MapStoreFirmware, ATruncatedMapIsRefusedAndMovedAside) {
  const RealRun& run = real_run();
  ASSERT_TRUE(run.ok) << run.why;
  const std::vector<std::uint8_t>& bytes = run.map_bytes;
  ASSERT_FALSE(bytes.empty());
  TempDir dir("cut_final");
  const std::string path = dir.file("map.bin");
  for (std::size_t k = 0; k < bytes.size(); k += 64) {
    write_bytes(path, bytes.data(), k);
    MapStore store(options(path));
    const MapStore::StartCheck c = store.check_at_start();
    ASSERT_EQ(c.found, MapStore::Found::kRefused) << "cut at " << k << ": " << all_text(c);
    const mf::Refusal expected =
        k < mf::kHeaderSize + 4 ? mf::Refusal::kTooShort : mf::Refusal::kSize;
    ASSERT_EQ(c.decoded.refusal, expected) << "cut at " << k;
    const std::string text = all_text(c);
    ASSERT_NE(text.find(path + ": refused: " + mf::to_string(expected) + " at byte "),
              std::string::npos)
        << text;
    ASSERT_NE(text.find("moved to " + path + ".refused"), std::string::npos) << text;
    ASSERT_NE(text.find("a new map starts"), std::string::npos) << text;
    ASSERT_EQ(text.find("replacing an older one") != std::string::npos, k > 0) << text;
    ASSERT_FALSE(fs::exists(path)) << "cut at " << k;
    ASSERT_EQ(fs::file_size(path + ".refused"), k) << "the refused file is not kept whole";
    ASSERT_EQ(store.snapshot().count, 0);
  }
}

// A byte flipped at offset k of the final file: refused every time (the CRC, or a check before it).
TEST(MapStoreFirmware, ADamagedMapIsNeverAccepted) {
  const RealRun& run = real_run();
  ASSERT_TRUE(run.ok) << run.why;
  ASSERT_FALSE(run.map_bytes.empty());
  TempDir dir("flip");
  const std::string path = dir.file("map.bin");
  int by_crc = 0;
  int checked = 0;
  for (std::size_t k = 0; k < run.map_bytes.size(); k += 64) {
    std::vector<std::uint8_t> bytes = run.map_bytes;
    bytes[k] ^= 0x5A;
    write_bytes(path, bytes.data(), bytes.size());
    MapStore store(options(path));
    const MapStore::StartCheck c = store.check_at_start();
    ASSERT_EQ(c.found, MapStore::Found::kRefused) << "flip at " << k << ": " << all_text(c);
    ASSERT_NE(c.decoded.refusal, mf::Refusal::kNone);
    ASSERT_EQ(read_bytes(path + ".refused"), bytes) << "flip at " << k;
    by_crc += c.decoded.refusal == mf::Refusal::kCrc ? 1 : 0;
    ++checked;
  }
  EXPECT_GT(checked, 100);
  EXPECT_GT(by_crc, checked / 2);
}

}  // namespace
}  // namespace cleanslam
