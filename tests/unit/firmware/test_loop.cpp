#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <string>

#include "allocation_counter.hpp"
#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/firmware/replay_check.hpp"
#include "cleanslam/firmware/run.hpp"
#include "cleanslam/firmware/systemd_notifier.hpp"
#include "fakes.hpp"

namespace cleanslam {
namespace {

namespace fs = std::filesystem;
using firmware::Loop;
using firmware::LoopOptions;
using firmware::Reject;
using firmware::RunEnd;
using firmware::VirtualClock;
using hal::SensorEvent;
using test::CollectingSink;
using test::FakeEstimator;
using test::ScriptedSource;

using test::kMs;
using test::kS;
using test::never_silent;

struct Rig {
  FakeEstimator est;
  ScriptedSource src;
  CollectingSink sink;
  VirtualClock clock;
  LoopOptions options;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> changes;

  struct Observer : firmware::HealthObserver {
    Rig* rig = nullptr;
    void health_changed(std::int64_t, std::uint32_t before, std::uint32_t after) override {
      rig->changes.emplace_back(before, after);
    }
  } observer;

  RunEnd run(Loop& loop) {
    loop.add_source(&src);
    loop.add_pose_sink(&sink);
    observer.rig = this;
    loop.set_health_observer(&observer);
    return firmware::run_virtual(loop, clock, false, nullptr);
  }
  // Poses whose time lies in [t0, t1).
  template <typename F>
  void for_poses(hal::TimeNs t0, hal::TimeNs t1, F f) const {
    for (const auto& p : sink.poses) {
      if (p.t_ns >= t0 && p.t_ns < t1) {
        f(p);
      }
    }
  }
};

TEST(Loop, NominalRunPublishesAt20HzPredictsPerEncoderAndProcessesFrames) {
  Rig rig;
  rig.src.drive(1 * kS, 4 * kS, 2.0, never_silent());
  Loop loop(rig.options, rig.est);
  EXPECT_EQ(rig.run(loop), RunEnd::kSourcesExhausted);
  EXPECT_EQ(loop.stats().gyro, 300U);
  EXPECT_EQ(loop.stats().encoders, 60U);
  EXPECT_EQ(rig.est.predictions, 60);
  EXPECT_EQ(loop.stats().frames_done, 6U);
  EXPECT_EQ(loop.stats().update_records, 36U);
  EXPECT_EQ(loop.stats().rejects.total(), 0U);
  // Published every 50 ms from the start; none flagged.
  ASSERT_GE(rig.sink.poses.size(), 59U);
  ASSERT_LE(rig.sink.poses.size(), 60U);
  for (std::size_t i = 1; i < rig.sink.poses.size(); ++i) {
    EXPECT_EQ(rig.sink.poses[i].t_ns - rig.sink.poses[i - 1].t_ns, 50 * kMs);
    EXPECT_EQ(rig.sink.poses[i].health, hal::kHealthOk) << i;
  }
  EXPECT_EQ(rig.sink.flushes, 1);
}

TEST(Loop, GyroSilenceFallsBackToEncoderHeadingAndRecovers) {
  Rig rig;
  rig.src.drive(1 * kS, 4 * kS, 2.0, [](SensorEvent::Kind k, hal::TimeNs t) {
    return k == SensorEvent::Kind::kGyro && t >= 2 * kS && t < 2500 * kMs;
  });
  Loop loop(rig.options, rig.est);
  rig.run(loop);
  // Silent from 1.99 s + 100 ms: flagged within one publication period, cleared on return.
  rig.for_poses(2150 * kMs, 2500 * kMs, [](const hal::PoseEstimate& p) {
    EXPECT_NE(p.health & hal::kGyroSilent, 0U) << p.t_ns;
  });
  rig.for_poses(2550 * kMs, 4 * kS, [](const hal::PoseEstimate& p) {
    EXPECT_EQ(p.health & hal::kGyroSilent, 0U) << p.t_ns;
  });
  rig.for_poses(1 * kS, 2050 * kMs, [](const hal::PoseEstimate& p) {
    EXPECT_EQ(p.health & hal::kGyroSilent, 0U) << p.t_ns;
  });
  EXPECT_EQ(rig.est.predictions, 60);
  ASSERT_EQ(rig.changes.size(), 2U);
  EXPECT_EQ(rig.changes[0].second, hal::kGyroSilent);
  EXPECT_EQ(rig.changes[1].second, hal::kHealthOk);
}

TEST(Loop, EncoderSilencePredictsAtEachEstimateAndRecovers) {
  Rig rig;
  rig.src.drive(1 * kS, 4 * kS, 2.0, [](SensorEvent::Kind k, hal::TimeNs t) {
    return k == SensorEvent::Kind::kEncoder && t >= 2 * kS && t < 3 * kS;
  });
  Loop loop(rig.options, rig.est);
  rig.run(loop);
  // 40 at the encoder samples, and one per estimate published while they are silent (from
  // 2.2 s + the 0.25 s timeout to 3 s, at 20 Hz).
  EXPECT_GE(rig.est.predictions, 40 + 14);
  EXPECT_LE(rig.est.predictions, 40 + 16);
  rig.for_poses(2250 * kMs, 3 * kS, [](const hal::PoseEstimate& p) {
    EXPECT_NE(p.health & hal::kEncodersSilent, 0U) << p.t_ns;
  });
  rig.for_poses(3 * kS, 4 * kS, [](const hal::PoseEstimate& p) {
    EXPECT_EQ(p.health & hal::kEncodersSilent, 0U) << p.t_ns;
  });
  // The fake estimator's distance comes from the encoders alone: frozen during the gap.
  double d_before = 0.0;
  double d_after = 0.0;
  rig.for_poses(2250 * kMs, 2300 * kMs,
                [&](const hal::PoseEstimate& p) { d_before = p.position_m[0]; });
  rig.for_poses(2950 * kMs, 3000 * kMs,
                [&](const hal::PoseEstimate& p) { d_after = p.position_m[0]; });
  EXPECT_NE(d_before, 0.0);
  EXPECT_NEAR(std::hypot(d_after, 0.0), std::hypot(d_before, 0.0), 0.05);
}

TEST(Loop, CameraSilenceIsFlaggedAndDeadReckoningContinues) {
  Rig rig;
  rig.src.drive(1 * kS, 9 * kS, 2.0, [](SensorEvent::Kind k, hal::TimeNs t) {
    return k == SensorEvent::Kind::kFrame && t >= 2 * kS && t < 7 * kS;
  });
  Loop loop(rig.options, rig.est);
  rig.run(loop);
  rig.for_poses(5 * kS, 7 * kS, [](const hal::PoseEstimate& p) {
    EXPECT_EQ(p.health, hal::kCameraSilent) << p.t_ns;
  });
  rig.for_poses(7 * kS, 9 * kS,
                [](const hal::PoseEstimate& p) { EXPECT_EQ(p.health, hal::kHealthOk) << p.t_ns; });
  EXPECT_EQ(rig.est.predictions, 160);
  EXPECT_EQ(loop.stats().frames_done, 2U + 4U);
}

TEST(Loop, BadInputIsCountedByReasonAndNeverStopsTheLoop) {
  Rig rig;
  auto& s = rig.src;
  s.drive(1 * kS, 2 * kS, 2.0, never_silent());
  s.gyro(2 * kS, std::nan(""));       // non-finite
  s.gyro(1500 * kMs, 0.1);            // before the last one: out of order
  s.items.push_back(s.items.back());  // duplicate: out of order
  s.items.back().due = 2 * kS;
  s.gyro(2001 * kMs, 0.1);
  s.items.back().ev.gyro.t_ns = 60 * kS;  // stamped a minute ahead: a time jump
  s.encoder(2001 * kMs, 0, 0);
  s.encoder(2000 * kMs, 0, 0);  // out of order
  const auto tail = s.items.size();
  s.drive(2010 * kMs, 3 * kS, 2.0, never_silent());
  (void)tail;
  Loop loop(rig.options, rig.est);
  EXPECT_EQ(rig.run(loop), RunEnd::kSourcesExhausted);
  const auto& r = loop.stats().rejects;
  EXPECT_EQ(r[Reject::kNonFinite], 1U);
  EXPECT_EQ(r[Reject::kTimeJump], 1U);
  // Out of order: the late gyro, its duplicate, the late encoder, and the second drive's first
  // encoder sample at 2.01 s is fine; its t=2.0 frame is not sent.
  EXPECT_EQ(r[Reject::kOutOfOrder], 3U);
  EXPECT_EQ(rig.est.last_gyro, 2990 * kMs);
  // The estimates after the bad input (ingested at 2.0 s and 2.001 s) say so, then are clean.
  int flagged = 0;
  rig.for_poses(2 * kS, 3 * kS, [&](const hal::PoseEstimate& p) {
    flagged += (p.health & hal::kInputRejected) != 0 ? 1 : 0;
  });
  EXPECT_EQ(flagged, 2);
  EXPECT_EQ(rig.sink.poses.back().health, hal::kHealthOk);
}

TEST(Loop, KeepsTheNewestFrameAtTheConfiguredRate) {
  Rig rig;
  rig.src.drive(1 * kS, 3 * kS, 10.0, never_silent());  // a 10 Hz camera
  rig.options.frame_rate_hz = 2.0;
  Loop loop(rig.options, rig.est);
  rig.run(loop);
  EXPECT_EQ(loop.stats().frames_in, 20U);
  EXPECT_EQ(loop.stats().frames_done, 4U);
  EXPECT_EQ(loop.stats().rejects[Reject::kFrameRate], 16U);
}

TEST(Loop, AWaitingFrameIsReplacedByANewerOne) {
  // Frames of 60 features every 100 ms, one feature per iteration, iterations every 10 ms: a
  // frame takes 600 ms, so waiting frames are replaced by newer ones.
  Rig rig;
  rig.options.frame_work_budget = 1;
  rig.options.frame_rate_hz = 10.0;
  for (hal::TimeNs t = 1 * kS; t < 3 * kS; t += 100 * kMs) {
    rig.src.frame(t, 60);
  }
  Loop loop(rig.options, rig.est);
  loop.add_source(&rig.src);
  loop.start(1 * kS);
  for (hal::TimeNs t = 1 * kS; t < 3 * kS; t += 10 * kMs) {
    loop.iterate(t);
  }
  const auto& st = loop.stats();
  EXPECT_EQ(st.frames_in, 20U);
  EXPECT_EQ(st.frames_done, 3U);  // begun at 1.0, 1.6, 2.2 s
  // 2.8 s is being processed and 2.9 s waits at the end; all others were replaced.
  EXPECT_EQ(st.rejects[Reject::kFrameSuperseded], 20U - 3U - 2U);
  EXPECT_TRUE(loop.frame_work_pending());
  EXPECT_EQ(rig.est.frames_begun, 4);
}

TEST(Loop, BadFramesAndFeaturesAreCounted) {
  Rig rig;
  rig.src.drive(1 * kS, 2 * kS, 2.0, never_silent());
  rig.src.frame(1200 * kMs, 0);  // nothing in it... but also inside the rate limit
  rig.src.frame(2 * kS, 3);
  rig.src.features.back()[1].u_px = std::numeric_limits<double>::infinity();
  rig.src.items.back().ev.frame.features = rig.src.features.back().data();
  rig.src.frame(2600 * kMs, 0);
  Loop loop(rig.options, rig.est);
  rig.run(loop);
  EXPECT_EQ(loop.stats().rejects[Reject::kBadFeature], 1U);
  EXPECT_EQ(loop.stats().rejects[Reject::kBadFrame], 1U);
  EXPECT_EQ(rig.est.frame.feature_count, 2);
}

TEST(Loop, LiftedRobotLosesThePoseAndStartsANewMapWhenSetDown) {
  Rig rig;
  rig.src.drive(1 * kS, 2 * kS, 2.0, never_silent());
  const auto lift = [&](hal::TimeNs t, bool lifted) {
    hal::SensorEvent ev;
    ev.kind = SensorEvent::Kind::kLift;
    ev.lifted = lifted;
    rig.src.items.push_back({t, ev});
  };
  lift(2 * kS, true);
  rig.src.drive(2 * kS, 3 * kS, 2.0, [](SensorEvent::Kind k, hal::TimeNs) {
    return k != SensorEvent::Kind::kFrame;  // frames while lifted are not processed
  });
  lift(3 * kS, false);
  rig.src.drive(3 * kS, 4 * kS, 2.0, never_silent());
  Loop loop(rig.options, rig.est);
  rig.run(loop);
  rig.for_poses(2 * kS, 3 * kS, [](const hal::PoseEstimate& p) {
    EXPECT_EQ(p.health & (hal::kLifted | hal::kPoseLost), hal::kLifted | hal::kPoseLost) << p.t_ns;
  });
  rig.for_poses(3 * kS, 4 * kS, [](const hal::PoseEstimate& p) {
    EXPECT_EQ(p.health & (hal::kLifted | hal::kPoseLost), 0U) << p.t_ns;
  });
  EXPECT_EQ(rig.est.resets, 2);  // start, and set down
  EXPECT_EQ(loop.stats().frames_done, 2U + 2U);
}

TEST(Loop, RealtimePacingFollowsTheWallClock) {
  Rig rig;
  rig.src.drive(1 * kS, 1300 * kMs, 2.0, never_silent());
  Loop loop(rig.options, rig.est);
  loop.add_source(&rig.src);
  firmware::MonotonicClock wall;
  const hal::TimeNs t0 = wall.now();
  firmware::run_virtual(loop, rig.clock, true, nullptr);
  const hal::TimeNs elapsed = wall.now() - t0;
  EXPECT_GE(elapsed, 280 * kMs);
  EXPECT_EQ(loop.stats().gyro, 30U);
}

TEST(Loop, StopSignalEndsTheRunCleanly) {
  Rig rig;
  rig.src.drive(1 * kS, 100 * kS, 2.0, never_silent());
  struct RaisingSink : hal::PoseSink {
    int n = 0;
    void publish(const hal::PoseEstimate&) override {
      if (++n == 10) {
        std::raise(SIGTERM);
      }
    }
  } raising;
  Loop loop(rig.options, rig.est);
  firmware::StopSignals signals;
  loop.add_source(&rig.src);
  loop.add_pose_sink(&raising);
  loop.add_pose_sink(&rig.sink);
  EXPECT_EQ(firmware::run_virtual(loop, rig.clock, false, &signals), RunEnd::kStopped);
  EXPECT_TRUE(firmware::StopSignals::requested());
  EXPECT_EQ(rig.sink.poses.size(), 10U);
  EXPECT_EQ(rig.sink.flushes, 1);
  firmware::StopSignals::reset();
}

TEST(Loop, TellsSystemdReadyWatchdogAndStopping) {
  const fs::path sock =
      fs::temp_directory_path() / ("cleanslam_notify_" + std::to_string(::getpid()));
  fs::remove(sock);
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", sock.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);

  firmware::SystemdNotifier notifier(sock.string(), 400'000);  // kicks every 200 ms
  ASSERT_TRUE(notifier.active());
  EXPECT_EQ(notifier.watchdog_period_ns(), 200 * kMs);
  Rig rig;
  rig.src.drive(1 * kS, 2 * kS, 2.0, never_silent());
  Loop loop(rig.options, rig.est);
  loop.set_notifier(&notifier);
  rig.run(loop);
  std::vector<std::string> got;
  char buf[64];
  ssize_t n = 0;
  while ((n = ::recv(fd, buf, sizeof buf, MSG_DONTWAIT)) > 0) {
    got.emplace_back(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  fs::remove(sock);
  ASSERT_GE(got.size(), 3U);
  EXPECT_EQ(got.front(), "READY=1");
  EXPECT_EQ(got.back(), "STOPPING=1");
  const auto kicks = std::count(got.begin(), got.end(), std::string("WATCHDOG=1"));
  EXPECT_GE(kicks, 5);
  EXPECT_LE(kicks, 6);
}

TEST(Loop, NoHeapAllocationAfterStartup) {
  const fs::path dir =
      fs::temp_directory_path() / ("cleanslam_alloc_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Rig rig;
  rig.src.drive(1 * kS, 20 * kS, 2.0, [](SensorEvent::Kind k, hal::TimeNs t) {
    return k == SensorEvent::Kind::kGyro && t > 5 * kS && t < 6 * kS;
  });
  rig.src.gyro(20 * kS, std::nan(""));
  firmware::Recorder rec;
  firmware::RecorderOptions ro;
  ro.path = (dir / "a.log").string();
  ro.max_file_bytes = 64 << 10;  // rotations happen inside the measured span
  std::string error;
  ASSERT_TRUE(rec.open(ro, "x: 1\n", error));
  Loop loop(rig.options, rig.est);
  loop.add_source(&rig.src);
  loop.add_pose_sink(&rig.sink);
  loop.set_recorder(&rec);
  loop.start(1 * kS);
  std::size_t allocations = 0;
  {
    test::AllocationScope scope;
    for (hal::TimeNs t = 1 * kS; t <= 21 * kS; t += 5 * kMs) {
      loop.iterate(t);
    }
    allocations = scope.count();
  }
  loop.finish();
  EXPECT_EQ(allocations, 0U);
  EXPECT_GT(rec.stats().rotations, 0U);
  EXPECT_EQ(loop.stats().frames_done, 38U);
  EXPECT_EQ(loop.stats().rejects[Reject::kNonFinite], 1U);
  fs::remove_all(dir);
}

// Records a run, replays the log through a fresh loop at the recorded iterations, and compares.
TEST(Replay, ReproducesTheRecordedOutputsBitForBit) {
  const fs::path dir =
      fs::temp_directory_path() / ("cleanslam_replay_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string error;
  {
    Rig rig;
    rig.src.drive(1 * kS, 6 * kS, 2.0, [](SensorEvent::Kind k, hal::TimeNs t) {
      return k == SensorEvent::Kind::kGyro && t > 2 * kS && t < 2300 * kMs;
    });
    rig.src.gyro(6 * kS, std::nan(""));
    firmware::Recorder rec;
    firmware::RecorderOptions ro;
    ro.path = (dir / "run.log").string();
    ASSERT_TRUE(rec.open(ro, "cfg: 1\n", error));
    Loop loop(rig.options, rig.est);
    loop.set_recorder(&rec);
    rig.run(loop);
  }
  readers::LogReader original;
  ASSERT_TRUE(original.open((dir / "run.log").string()));
  const auto replay = [&](const std::string& out, double tweak) {
    FakeEstimator est;
    est.yaw = tweak;
    readers::LogSource src(original, readers::LogSource::Pacing::kRecordedTicks);
    firmware::Recorder rec;
    firmware::RecorderOptions ro;
    ro.path = (dir / out).string();
    EXPECT_TRUE(rec.open(ro, original.config_text(), error));
    LoopOptions options;
    Loop loop(options, est);
    loop.add_source(&src);
    loop.set_recorder(&rec);
    VirtualClock clock;
    firmware::run_recorded(loop, clock, src, nullptr);
    rec.close();
    readers::LogReader replayed;
    EXPECT_TRUE(replayed.open(ro.path));
    return firmware::compare_outputs(original, replayed);
  };
  const auto same = replay("replay.log", 0.0);
  EXPECT_TRUE(same.identical) << same.description;
  EXPECT_GT(same.original_outputs, 100U);
  EXPECT_EQ(same.original_outputs, same.replayed_outputs);
  // A different estimator state shows up as the first differing record.
  const auto differs = replay("replay2.log", 1e-12);
  EXPECT_FALSE(differs.identical);
  EXPECT_EQ(differs.first_difference, 0U);
  EXPECT_NE(differs.description.find("offset"), std::string::npos) << differs.description;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cleanslam
