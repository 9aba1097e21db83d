#include <pthread.h>
#include <sys/mman.h>
#include <ucontext.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <span>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "allocation_counter.hpp"
#include "cleanslam/slam_core/dead_reckoner.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "pose_solve_scenario.hpp"

namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

// Runs fn on a small stack of its own with a guard page below it: a megabyte temporary on the stack
// would crash the test. The stack is a ucontext, not a thread, because qemu-aarch64 7.2 user mode
// hangs in pthread_create here; under ASan (which does not follow swapcontext) it is a thread.
// Returns the bytes of stack fn touched (high-water mark), or 0 when not measured.
#if !defined(__SANITIZE_ADDRESS__)
void (*g_body)(void*) = nullptr;
void* g_arg = nullptr;
ucontext_t g_main_ctx;
ucontext_t g_work_ctx;

void context_entry() {
  g_body(g_arg);
}
#endif

template <typename Fn>
std::size_t run_with_small_stack(Fn& fn) {
#if defined(__SANITIZE_ADDRESS__)
  constexpr std::size_t kStack = 1024 * 1024;  // ASan's redzones inflate every frame
  pthread_attr_t attr;
  EXPECT_EQ(pthread_attr_init(&attr), 0);
  EXPECT_EQ(pthread_attr_setstacksize(&attr, kStack), 0);
  pthread_t thread;
  auto trampoline = [](void* p) -> void* {
    (*static_cast<Fn*>(p))();
    return nullptr;
  };
  EXPECT_EQ(pthread_create(&thread, &attr, trampoline, &fn), 0);
  EXPECT_EQ(pthread_join(thread, nullptr), 0);
  pthread_attr_destroy(&attr);
  return 0;
#else
  constexpr std::size_t kStack = 256 * 1024;
  constexpr std::size_t kGuard = 64 * 1024;
  constexpr unsigned char kFill = 0xA5;
  void* mem =
      mmap(nullptr, kStack + kGuard, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  EXPECT_NE(mem, MAP_FAILED);
  auto* base = static_cast<unsigned char*>(mem);
  EXPECT_EQ(mprotect(base, kGuard, PROT_NONE), 0);
  std::memset(base + kGuard, kFill, kStack);
  g_body = [](void* p) { (*static_cast<Fn*>(p))(); };
  g_arg = &fn;
  EXPECT_EQ(getcontext(&g_work_ctx), 0);
  g_work_ctx.uc_stack.ss_sp = base + kGuard;
  g_work_ctx.uc_stack.ss_size = kStack;
  g_work_ctx.uc_link = &g_main_ctx;
  makecontext(&g_work_ctx, context_entry, 0);
  EXPECT_EQ(swapcontext(&g_main_ctx, &g_work_ctx), 0);
  std::size_t untouched = 0;
  while (untouched < kStack && base[kGuard + untouched] == kFill) {
    ++untouched;
  }
  munmap(mem, kStack + kGuard);
  return kStack - untouched;
#endif
}

struct EkfRun {
  cs::Ekf* ekf = nullptr;
  std::size_t allocations = 0;
  int updates_applied = 0;
  int initialized = 0;
  int continued = 0;  // continue_update() calls of chunked updates
  int merged = 0;     // a landmark's duplicate merged back (Ekf::merge_landmarks)
  bool finite = true;

  void operator()() {
    Eigen::internal::set_is_malloc_allowed(false);
    const cleanslam::test::AllocationScope scope;
    std::array<cs::Observation, hal::kMaxObservationsPerFrame> obs{};
    std::array<double, 2 * hal::kMaxObservationsPerFrame> nu{};
    std::array<double, 4 * hal::kMaxObservationsPerFrame * hal::kMaxObservationsPerFrame> S{};
    // 80 steps: at 3 a step the pool (128) is full by step 43, and the rest recycle it; emulated,
    // each run takes seconds.
    for (int step = 0; step < 80; ++step) {
      cs::OdometryIncrement u;
      u.dx_c = Eigen::Vector3d(0.05, 0.0, 0.0);
      u.dpsi_c = Eigen::Vector3d(0.0, 0.0, step % 40 < 20 ? 0.02 : -0.02);
      u.Q.diagonal() << 1e-5, 1e-6, 1e-7, 1e-7, 1e-7, 1e-6;
      u.dt_s = 0.5;
      ekf->predict(u);
      // New landmarks every step: the pool fills and then recycles its least useful slots.
      for (int k = 0; k < 3; ++k) {
        const double uu = 20.0 + static_cast<double>((step * 7 + k * 97) % 280);
        const double vv = 20.0 + static_cast<double>((step * 13 + k * 61) % 200);
        if (ekf->initialize_landmark(uu, vv) >= 0) {
          ++initialized;
        }
      }
      int m = 0;
      for (int slot = 0; slot < hal::kMaxLandmarks && m < 10; ++slot) {
        cs::PixelPrediction p;
        if (ekf->predict_pixel(slot, p) && ekf->camera().in_image(p.uv.x(), p.uv.y())) {
          obs[static_cast<std::size_t>(m++)] = {slot, p.uv.x() + 0.3, p.uv.y() - 0.2};
        }
      }
      ekf->joint_pixel_innovation(std::span(obs).first(static_cast<std::size_t>(m)), nu, S);
      ekf->update(obs.data(), m);
      // A chunked update runs to its end in steps, or (every 7th) is left pending for the next
      // prediction to finish.
      while (step % 7 != 3 && ekf->update_pending()) {
        ekf->continue_update();
        ++continued;
      }
      if (step % 7 == 3 && ekf->update_pending()) {
        ekf->predict(u);
      }
      if (ekf->last_update().applied) {
        ++updates_applied;
      }
      if (step % 50 == 49) {
        ekf->delete_landmark(step % hal::kMaxLandmarks);
      }
      // A duplicate of a landmark in view, from its predicted pixel, merged back into it.
      if (step % 9 == 5 && m > 0 && !ekf->update_pending()) {
        cs::PixelPrediction p;
        const int slot = obs[0].slot;
        if (ekf->predict_pixel(slot, p)) {
          const int dup = ekf->initialize_landmark(p.uv.x(), p.uv.y());
          if (dup >= 0 && dup != slot &&
              ekf->merge_landmarks(slot, dup, 11.34) == cs::ObservationResult::kFused) {
            ++merged;
          }
        }
      }
      const hal::PoseEstimate e = ekf->body_pose_estimate(step);
      finite = finite && std::isfinite(e.position_m[0]);
    }
    allocations = scope.count();
    Eigen::internal::set_is_malloc_allowed(true);
  }
};

}  // namespace

TEST(EstimatorAllocation, EkfLongRunAllocatesNothing) {
  hal::Calibration calibration;
  calibration.camera.distortion = {-0.1, 0.02, 0.0005, -0.0003};
  auto ekf = std::make_unique<cs::Ekf>(calibration, cs::EkfConfig{});
  cs::Matrix6d P0 = cs::Matrix6d::Identity() * 1e-6;
  EXPECT_TRUE(ekf->reset(cs::Vector6d::Zero(), P0));
  EkfRun run;
  run.ekf = ekf.get();
  const std::size_t stack = run_with_small_stack(run);
  std::printf("EKF run: stack high-water mark %zu bytes of 256 KiB\n", stack);
  EXPECT_EQ(run.allocations, 0U);
  EXPECT_GT(run.initialized, hal::kMaxLandmarks);  // the pool was full and recycled
  EXPECT_GT(ekf->counters().landmarks_replaced, 0U);
  EXPECT_GT(run.updates_applied, 50);
  EXPECT_GT(run.merged, 5);
  EXPECT_TRUE(run.finite);
  EXPECT_TRUE(ekf->state().allFinite());
  EXPECT_EQ(run.continued, 0);
}

TEST(EstimatorAllocation, EkfChunkedUpdatesAllocateNothing) {
  hal::Calibration calibration;
  calibration.camera.distortion = {-0.1, 0.02, 0.0005, -0.0003};
  auto ekf = std::make_unique<cs::Ekf>(calibration, cs::EkfConfig{});
  ekf->set_update_step(20000);
  cs::Matrix6d P0 = cs::Matrix6d::Identity() * 1e-6;
  EXPECT_TRUE(ekf->reset(cs::Vector6d::Zero(), P0));
  EkfRun run;
  run.ekf = ekf.get();
  const std::size_t stack = run_with_small_stack(run);
  std::printf("chunked EKF run: stack high-water mark %zu bytes of 256 KiB\n", stack);
  EXPECT_EQ(run.allocations, 0U);
  EXPECT_GT(run.initialized, hal::kMaxLandmarks);
  EXPECT_GT(run.updates_applied, 50);
  EXPECT_GT(run.continued, 10 * run.updates_applied);  // many bounded steps per update
  EXPECT_TRUE(run.finite);
  EXPECT_TRUE(ekf->state().allFinite());
}

// EkfRun with this configuration for each update step (0: one-shot); returns the last run's filter.
std::unique_ptr<cs::Ekf> expect_no_allocation(const hal::Calibration& calibration,
                                              const cs::EkfConfig& config,
                                              std::initializer_list<std::int64_t> steps) {
  std::unique_ptr<cs::Ekf> ekf;
  for (const std::int64_t step : steps) {
    ekf = std::make_unique<cs::Ekf>(calibration, config);
    ekf->set_update_step(step);
    EXPECT_TRUE(ekf->reset(cs::Vector6d::Zero(), cs::Matrix6d::Identity() * 1e-6));
    EkfRun run;
    run.ekf = ekf.get();
    run_with_small_stack(run);
    EXPECT_EQ(run.allocations, 0U) << "step " << step;
    EXPECT_GT(run.updates_applied, 50);
    EXPECT_GT(run.merged, 5);
    EXPECT_TRUE(run.finite);
    EXPECT_TRUE(ekf->state().allFinite());
  }
  return ekf;
}

// The firmware's defaults: the invariant reset after every update and merge, and merges that
// consider the kept entry.
TEST(EstimatorAllocation, EkfWithInvariantResetAllocatesNothing) {
  cs::EkfConfig config;
  config.invariant_reset = true;
  config.merge_considers_kept = true;
  expect_no_allocation(hal::Calibration{}, config, {0, 20000});
}

namespace {

struct DeadReckonerRun {
  cs::DeadReckoner* dr = nullptr;
  std::size_t allocations = 0;
  double distance = 0.0;
  int encoders_silent_from_ms = -1;  // encoder outage [from, to)
  int encoders_silent_to_ms = -1;

  void operator()() {
    Eigen::internal::set_is_malloc_allowed(false);
    const cleanslam::test::AllocationScope scope;
    std::int32_t ticks = 2147480000;  // wraps during the run
    for (int ms = 0; ms <= 60000; ms += 10) {
      const hal::TimeNs t = ms * hal::kNsPerMillisecond;
      hal::GyroSample g;
      g.t_ns = t;
      g.wz_rad_s = (ms / 5000) % 2 == 0 ? 0.0 : 0.3;
      dr->add_gyro(g);
      if (ms % 50 == 0) {
        hal::EncoderSample e;
        e.t_ns = t;
        e.left_ticks = ticks;
        e.right_ticks = ticks;
        if (ms < encoders_silent_from_ms || ms >= encoders_silent_to_ms) {
          dr->add_encoder(e);
        }
        ticks = static_cast<std::int32_t>(static_cast<std::uint32_t>(ticks) + 40U);
      }
      if (ms % 700 == 0) {
        distance += dr->take_increment(t + 3 * hal::kNsPerMillisecond).distance_m;
      }
    }
    allocations = scope.count();
    Eigen::internal::set_is_malloc_allowed(true);
  }
};

}  // namespace

TEST(EstimatorAllocation, DeadReckonerLongRunAllocatesNothing) {
  const hal::Calibration calibration;
  cs::DeadReckoner dr(calibration, cs::DeadReckoningConfig{});
  DeadReckonerRun run;
  run.dr = &dr;
  const std::size_t stack = run_with_small_stack(run);
  std::printf("dead reckoner run: stack high-water mark %zu bytes of 256 KiB\n", stack);
  EXPECT_EQ(run.allocations, 0U);
  EXPECT_NEAR(run.distance, 59.503 * 0.2, 1e-3);  // up to the last take
}

TEST(EstimatorAllocation, DeadReckonerThroughAnEncoderOutageAllocatesNothing) {
  const hal::Calibration calibration;
  cs::DeadReckoner dr(calibration, cs::DeadReckoningConfig{});
  DeadReckonerRun run;
  run.dr = &dr;
  run.encoders_silent_from_ms = 20000;
  run.encoders_silent_to_ms = 40000;
  run_with_small_stack(run);
  EXPECT_EQ(run.allocations, 0U);
  EXPECT_EQ(dr.counters().encoder_outages, 1U);
}

TEST(EstimatorAllocation, DeadReckonerWithWheelYawFusionAllocatesNothing) {
  const hal::Calibration calibration;
  cs::DeadReckoningConfig config;
  config.wheel_yaw.enabled = true;
  cs::DeadReckoner dr(calibration, config);
  DeadReckonerRun run;
  run.dr = &dr;
  run_with_small_stack(run);
  EXPECT_EQ(run.allocations, 0U);
  // The run's wheels go straight while its gyro turns at times: both learning and taking windows
  // back to the gyro happen.
  const cs::WheelYawCounters& k = dr.wheel_yaw_fusion().counters();
  EXPECT_GT(k.windows_used, 5U);
  EXPECT_GT(k.windows_gated + k.intervals_gated, 5U);
  EXPECT_NEAR(run.distance, 59.503 * 0.2, 1e-3);
}

TEST(EstimatorAllocation, EkfUpdateFromASolvedPoseAllocatesNothing) {
  const hal::Calibration calibration;
  auto ekf = std::make_unique<cs::Ekf>(calibration, cs::EkfConfig{});
  const auto sc =
      cleanslam::test::make_pose_solve_scenario(*ekf, 0.4, 0.3, Eigen::Vector3d(0.35, -0.3, 0.25));
  std::size_t allocations = 0;
  {
    Eigen::internal::set_is_malloc_allowed(false);
    const cleanslam::test::AllocationScope scope;
    ekf->update(sc.obs.data(), sc.count);
    allocations = scope.count();
    Eigen::internal::set_is_malloc_allowed(true);
  }
  EXPECT_EQ(allocations, 0U);
  EXPECT_EQ(ekf->counters().pose_solves, 1U);
}
