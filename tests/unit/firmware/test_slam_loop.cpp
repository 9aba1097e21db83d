#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "allocation_counter.hpp"
#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/firmware/program.hpp"
#include "cleanslam/firmware/run.hpp"
#include "cleanslam/firmware/run_report.hpp"
#include "cleanslam/firmware/sinks.hpp"
#include "cleanslam/firmware/slam_estimator.hpp"
#include "cleanslam/readers/dataset_source.hpp"
#include "cleanslam/sim_hal/sim/simulator.hpp"
#include "fakes.hpp"

namespace cleanslam {
namespace {

namespace fs = std::filesystem;
using firmware::FirmwareConfig;
using firmware::Loop;
using firmware::SlamEstimator;

// A simulated run (features mode) loaded into memory as a scripted source.
struct SimulatedRun {
  test::ScriptedSource source;
  hal::Calibration calibration;
  bool ok = false;

  std::vector<std::vector<std::uint8_t>> images;

  explicit SimulatedRun(double duration_s, bool rendered = false) {
    const fs::path dir =
        fs::temp_directory_path() / ("cleanslam_slamloop_" + std::to_string(::getpid()));
    std::vector<std::string> overrides{"duration_s=" + std::to_string(duration_s)};
    if (rendered) {
      overrides.emplace_back("camera.mode=images");
    }
    auto scenario = sim_hal::sim::load_scenario("default-room", overrides);
    if (!scenario.ok() || !sim_hal::sim::simulate(*scenario, dir.string()).ok()) {
      return;
    }
    auto ds = readers::DatasetSource::open(dir.string());
    if (!ds.ok()) {
      return;
    }
    calibration = ds->calibration();
    source.features.reserve(100000);
    images.reserve(10000);
    hal::SensorEvent ev;
    while (ds->next_event_time() >= 0 && ds->read(ev)) {
      if (ev.kind == hal::SensorEvent::Kind::kFrame) {
        if (ev.frame.has_image()) {
          const auto& im = ev.frame.image;
          auto& copy = images.emplace_back(static_cast<std::size_t>(im.width * im.height));
          for (int y = 0; y < im.height; ++y) {
            std::memcpy(copy.data() + static_cast<std::size_t>(y * im.width), im.row(y),
                        static_cast<std::size_t>(im.width));
          }
          ev.frame.image = hal::GrayImageView{copy.data(), im.width, im.height, im.width};
        }
        if (ev.frame.has_features()) {
          source.features.emplace_back(ev.frame.features,
                                       ev.frame.features + ev.frame.feature_count);
          ev.frame.features = source.features.back().data();
        } else if (!ev.frame.has_image()) {
          continue;
        }
      }
      source.items.push_back({ev.kind == hal::SensorEvent::Kind::kGyro      ? ev.gyro.t_ns
                              : ev.kind == hal::SensorEvent::Kind::kEncoder ? ev.encoder.t_ns
                                                                            : ev.frame.t_ns,
                              ev});
    }
    fs::remove_all(dir);
    ok = !source.items.empty();
  }
};

// What print_summary writes at the end of a run; empty when no temporary file could be made.
std::string summary_text(const Loop& loop) {
  std::FILE* f = std::tmpfile();
  if (f == nullptr) {
    return {};
  }
  const firmware::CameraOffsetEstimate not_fed;
  firmware::print_summary(loop, not_fed, f);
  std::rewind(f);
  std::string text;
  for (int ch = std::fgetc(f); ch != EOF; ch = std::fgetc(f)) {
    text.push_back(static_cast<char>(ch));
  }
  std::fclose(f);
  return text;
}

namespace {

struct CountingByStatus : firmware::UpdateSink {
  std::array<std::uint64_t, hal::log::kUpdateStatusCount> n{};
  void update(const hal::log::UpdateRecord& r) override {
    ++n.at(static_cast<std::size_t>(r.status));
  }
};

// A SlamEstimator on the loop, run to the end of a simulated run, its records counted.
struct CountedRun {
  CountedRun(SimulatedRun& run, const FirmwareConfig& config)
      : estimator(config), loop(config.loop, estimator) {
    loop.add_source(&run.source);
    loop.add_update_sink(&counting);
    firmware::VirtualClock clock;
    firmware::run_virtual(loop, clock, false, nullptr);
  }
  SlamEstimator estimator;
  Loop loop;
  CountingByStatus counting;
};

}  // namespace

TEST(SlamLoop, NoHeapAllocationAfterStartupWithTheEkf) {
  SimulatedRun run(60.0);
  ASSERT_TRUE(run.ok);
  FirmwareConfig config;
  config.calibration = run.calibration;
  SlamEstimator estimator(config);
  Loop loop(config.loop, estimator);
  test::CollectingSink sink;
  CountingByStatus counting;
  loop.add_source(&run.source);
  loop.add_pose_sink(&sink);
  loop.add_update_sink(&counting);
  const hal::TimeNs t0 = run.source.items.front().due;
  const hal::TimeNs t1 = run.source.items.back().due;
  loop.start(t0);
  std::size_t allocations = 0;
  {
    test::AllocationScope scope;
    for (hal::TimeNs t = t0; t <= t1 + hal::kNsPerSecond; t += 5 * hal::kNsPerMillisecond) {
      loop.iterate(t);
    }
    allocations = scope.count();
  }
  loop.finish();
  EXPECT_EQ(allocations, 0U);
  EXPECT_GT(loop.stats().frames_done, 50U);
  EXPECT_GT(loop.stats().update_records, 200U);
  EXPECT_GT(estimator.ekf().landmark_count(), 5);
  EXPECT_EQ(loop.stats().rejects.total(), 0U);
}

// Rendered images through the front end's frame pipeline: a frame takes several loop iterations
// of one bounded step each, landmarks are tracked and fused, and nothing is allocated.
TEST(SlamLoop, ImageFramesGoThroughThePipelineInBoundedStepsWithoutAllocation) {
  SimulatedRun run(15.0, true);
  ASSERT_TRUE(run.ok);
  ASSERT_FALSE(run.images.empty());
  FirmwareConfig config;
  config.calibration = run.calibration;
  SlamEstimator estimator(config);
  Loop loop(config.loop, estimator);
  loop.add_source(&run.source);
  const hal::TimeNs t0 = run.source.items.front().due;
  const hal::TimeNs t1 = run.source.items.back().due;
  loop.start(t0);
  std::size_t allocations = 0;
  std::uint64_t iterations_with_frame_work = 0;
  {
    test::AllocationScope scope;
    for (hal::TimeNs t = t0; t <= t1 + hal::kNsPerSecond; t += 5 * hal::kNsPerMillisecond) {
      iterations_with_frame_work += loop.frame_work_pending() ? 1 : 0;
      loop.iterate(t);
    }
    allocations = scope.count();
  }
  EXPECT_EQ(allocations, 0U);
  EXPECT_EQ(estimator.image_frames(), loop.stats().frames_done);
  EXPECT_GE(loop.stats().frames_done, 25U);
  EXPECT_GT(iterations_with_frame_work, 3 * loop.stats().frames_done);  // several steps a frame
  EXPECT_GT(estimator.ekf().counters().updates_applied, 10U);
  EXPECT_GT(estimator.ekf().landmark_count(), 5);
}

// The summary at the end of a run counts how the map changed, as the filter counted it, and the
// update records by status, as the sinks received them.
TEST(SlamLoop, SummaryCountsTheMapsChangesAndTheRecords) {
  SimulatedRun run(30.0);
  ASSERT_TRUE(run.ok);
  FirmwareConfig config;
  config.calibration = run.calibration;
  config.slam.filter.max_landmarks = 8;  // a small pool: landmarks are replaced
  CountedRun counted(run, config);
  const SlamEstimator& estimator = counted.estimator;
  const Loop& loop = counted.loop;
  const CountingByStatus& counting = counted.counting;
  const auto& c = estimator.ekf().counters();
  ASSERT_GT(c.landmarks_initialized, 8U);
  ASSERT_GT(c.landmarks_replaced, 0U);
  const std::string text = summary_text(loop);
  ASSERT_FALSE(text.empty());
  const std::string line = "cleanslam: map: " + std::to_string(c.landmarks_initialized) +
                           " landmarks initialized, " + std::to_string(c.landmarks_replaced) +
                           " replaced, " + std::to_string(c.landmarks_deleted) + " deleted, " +
                           std::to_string(c.landmarks_merged) + " merged, " +
                           std::to_string(c.merges_gated) + " merges gated\n";
  EXPECT_NE(text.find(line), std::string::npos) << text;
  // The heading fusion's calibration (on by default), with the fusion's own counts.
  const auto& w = estimator.dead_reckoner().wheel_yaw_fusion().counters();
  ASSERT_GT(w.windows_used, 10U);
  const std::string fused = std::to_string(w.intervals_fused) + " intervals fused, " +
                            std::to_string(w.intervals_gated) + " gated, " +
                            std::to_string(w.windows_used) + " windows learnt, " +
                            std::to_string(w.windows_gated) + " taken back to the gyro\n";
  EXPECT_NE(text.find("cleanslam: wheel heading: scale "), std::string::npos) << text;
  EXPECT_NE(text.find(fused), std::string::npos) << text;
  ASSERT_GT(counting.n[0], 0U);  // updated
  EXPECT_EQ(loop.stats().records_by_status, counting.n);
  std::string by_status = "cleanslam: update records by status:";
  const char* separator = " ";
  for (std::size_t i = 0; i < counting.n.size(); ++i) {
    if (counting.n[i] > 0) {
      by_status.append(separator)
          .append(firmware::to_string(static_cast<hal::log::UpdateStatus>(i)))
          .append(" ")
          .append(std::to_string(counting.n[i]));
      separator = ", ";
    }
  }
  by_status.push_back('\n');
  EXPECT_NE(text.find(by_status), std::string::npos) << text;
}

// The estimator on the loop is deterministic: two runs, the same poses bit for bit.
TEST(SlamLoop, DeterministicAcrossRuns) {
  SimulatedRun run(30.0);
  ASSERT_TRUE(run.ok);
  const auto once = [&] {
    FirmwareConfig config;
    config.calibration = run.calibration;
    SlamEstimator estimator(config);
    Loop loop(config.loop, estimator);
    test::CollectingSink sink;
    test::ScriptedSource src = run.source;
    src.next = 0;
    loop.add_source(&src);
    loop.add_pose_sink(&sink);
    firmware::VirtualClock clock;
    firmware::run_virtual(loop, clock, false, nullptr);
    return sink.poses;
  };
  const auto a = once();
  const auto b = once();
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 500U);
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(std::memcmp(a[i].position_m.data(), b[i].position_m.data(), 24), 0) << i;
    ASSERT_EQ(std::memcmp(a[i].covariance.data(), b[i].covariance.data(), 36 * 8), 0) << i;
  }
  const auto& last = a.back().position_m;
  EXPECT_TRUE(std::isfinite(last[0]) && std::isfinite(last[1]));
}

// The EKF update bounded per loop iteration (loop.frame_work_budget) gives the same estimate as
// the update at once: on a virtual clock the loop does not advance time while a frame is pending,
// so the frame poses are the same bit for bit; only the iterations differ.
TEST(SlamLoop, BoundedUpdatesGiveTheOneShotEstimate) {
  SimulatedRun run(30.0);
  ASSERT_TRUE(run.ok);
  struct Result {
    std::vector<hal::PoseEstimate> frames;
    std::uint64_t iterations = 0;
    std::uint64_t updates = 0;
  };
  const auto once = [&](int budget) {
    FirmwareConfig config;
    config.calibration = run.calibration;
    config.loop.frame_work_budget = budget;
    SlamEstimator estimator(config);
    Loop loop(config.loop, estimator);
    test::CollectingSink frames;
    test::ScriptedSource src = run.source;
    src.next = 0;
    loop.add_source(&src);
    loop.add_frame_sinks(&frames, nullptr);
    firmware::VirtualClock clock;
    firmware::run_virtual(loop, clock, false, nullptr);
    return Result{frames.poses, loop.stats().iterations,
                  estimator.ekf().counters().updates_applied};
  };
  const Result chunked = once(1);
  const Result whole = once(1 << 20);
  ASSERT_GT(whole.frames.size(), 40U);
  ASSERT_EQ(chunked.frames.size(), whole.frames.size());
  EXPECT_GT(whole.updates, 20U);
  EXPECT_EQ(chunked.updates, whole.updates);
  EXPECT_GT(chunked.iterations, whole.iterations + 10 * whole.updates);  // many steps an update
  for (std::size_t i = 0; i < whole.frames.size(); ++i) {
    ASSERT_EQ(
        std::memcmp(chunked.frames[i].position_m.data(), whole.frames[i].position_m.data(), 24), 0)
        << i;
    ASSERT_EQ(
        std::memcmp(chunked.frames[i].covariance.data(), whole.frames[i].covariance.data(), 36 * 8),
        0)
        << i;
  }
}

// On a clock that keeps running (5 ms ticks), samples arrive while an update is pending: the
// prediction waits for it and then takes the whole increment at once, so there are fewer
// predictions; the estimate stays close to the one-shot one.
TEST(SlamLoop, PredictionWaitsForAPendingUpdate) {
  SimulatedRun run(30.0);
  ASSERT_TRUE(run.ok);
  struct Result {
    hal::PoseEstimate last;
    std::uint64_t predictions = 0;
    std::uint64_t updates = 0;
  };
  const auto once = [&](int budget) {
    FirmwareConfig config;
    config.calibration = run.calibration;
    config.loop.frame_work_budget = budget;
    SlamEstimator estimator(config);
    Loop loop(config.loop, estimator);
    test::ScriptedSource src = run.source;
    src.next = 0;
    loop.add_source(&src);
    const hal::TimeNs t0 = src.items.front().due;
    const hal::TimeNs t1 = src.items.back().due;
    loop.start(t0);
    for (hal::TimeNs t = t0; t <= t1 + hal::kNsPerSecond; t += 5 * hal::kNsPerMillisecond) {
      loop.iterate(t);
    }
    loop.finish();
    return Result{estimator.pose(t1), estimator.ekf().counters().predictions,
                  estimator.ekf().counters().updates_applied};
  };
  const Result chunked = once(1);
  const Result whole = once(1 << 20);
  EXPECT_GT(whole.updates, 20U);
  EXPECT_GT(chunked.updates, whole.updates / 2);
  EXPECT_LT(chunked.predictions, whole.predictions);
  const double dx = chunked.last.position_m[0] - whole.last.position_m[0];
  const double dy = chunked.last.position_m[1] - whole.last.position_m[1];
  EXPECT_LT(std::hypot(dx, dy), 0.05);
}

}  // namespace
}  // namespace cleanslam
