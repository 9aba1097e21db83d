#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#include <benchmark/benchmark.h>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/slam_core/ekf.hpp"

// The estimator's hot calls: prediction, one batch update of 10 observations at several map
// sizes, and the undelayed initialization of one landmark (eq. 39-45).
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

cs::OdometryIncrement step_increment() {
  cs::OdometryIncrement u;
  u.dx_c = Eigen::Vector3d(0.1, 0.0, 0.0);
  u.dpsi_c = Eigen::Vector3d(0.0, 0.0, 0.02);
  u.Q.diagonal() << 1e-5, 1e-6, 1e-7, 1e-7, 1e-7, 1e-6;
  return u;
}

// An EKF with `landmarks` slots in use, spread over the image, after some motion.
std::unique_ptr<cs::Ekf> make_filter(int landmarks, bool invariant_reset = false,
                                     bool merge_considers_kept = false) {
  hal::Calibration calibration;
  cs::EkfConfig config;
  config.invariant_reset = invariant_reset;
  config.merge_considers_kept = merge_considers_kept;
  auto ekf = std::make_unique<cs::Ekf>(calibration, config);
  if (!ekf->reset(cs::Vector6d::Zero(), cs::Matrix6d::Identity() * 1e-6)) {
    std::fprintf(stderr, "bench_estimator: the filter refused its start\n");
    std::abort();
  }
  for (int i = 0; ekf->landmark_count() < landmarks && i < 10 * hal::kMaxLandmarks; ++i) {
    if (i % 10 == 0) {
      ekf->predict(step_increment());
    }
    const double u = 10.0 + static_cast<double>((i * 37) % 300);
    const double v = 10.0 + static_cast<double>((i * 53) % 220);
    ekf->initialize_landmark(u, v);
  }
  ekf->predict(step_increment());
  return ekf;
}

void BM_Predict(benchmark::State& state) {
  auto ekf = make_filter(static_cast<int>(state.range(0)));
  const cs::OdometryIncrement u = step_increment();
  for (auto _ : state) {
    benchmark::DoNotOptimize(ekf->predict(u));
  }
  state.counters["state_dim"] = ekf->active_dim();
}
BENCHMARK(BM_Predict)->Arg(25)->Arg(100)->Arg(128);

// range(1): with EkfConfig::invariant_reset.
void BM_Update10(benchmark::State& state) {
  auto ekf = make_filter(static_cast<int>(state.range(0)), state.range(1) != 0);
  std::array<cs::Observation, 10> obs{};
  int m = 0;
  for (int slot = 0; slot < hal::kMaxLandmarks && m < 10; ++slot) {
    cs::PixelPrediction p;
    if (ekf->predict_pixel(slot, p) && ekf->camera().in_image(p.uv.x(), p.uv.y())) {
      obs[static_cast<std::size_t>(m++)] = {slot, p.uv.x() + 0.2, p.uv.y() - 0.1};
    }
  }
  int fused = 0;
  for (auto _ : state) {
    fused = ekf->update(obs.data(), m).fused;
    benchmark::ClobberMemory();
  }
  state.counters["state_dim"] = ekf->active_dim();
  state.counters["fused"] = fused;
}
BENCHMARK(BM_Update10)
    ->ArgsProduct({{25, 50, 100, 128}, {0, 1}})
    ->ArgNames({"landmarks", "invariant_reset"})
    ->Unit(benchmark::kMicrosecond);

// Initializes one landmark into a map of range(0) landmarks and deletes it again (the pair is
// timed; deletion is two row/column clears).
void BM_InitializeLandmark(benchmark::State& state) {
  auto ekf = make_filter(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const int slot = ekf->initialize_landmark(200.0, 90.0);
    benchmark::DoNotOptimize(slot);
    ekf->delete_landmark(slot);
  }
  state.counters["state_dim"] = ekf->active_dim();
}
BENCHMARK(BM_InitializeLandmark)->Arg(25)->Arg(100)->Unit(benchmark::kMicrosecond);

// A second entry of the first landmark in view, from a ray half a pixel off its prediction, with
// its depth unknown (as remapping makes one); -1 when none is in view.
__attribute__((noinline)) int make_duplicate(cs::Ekf& ekf, int& keep) {
  for (keep = 0; keep < hal::kMaxLandmarks; ++keep) {
    cs::PixelPrediction p;
    if (ekf.predict_pixel(keep, p) && ekf.camera().in_image(p.uv.x(), p.uv.y())) {
      return ekf.initialize_landmark(p.uv.x() + 0.5, p.uv.y() - 0.5);
    }
  }
  return -1;
}

// Merges such a duplicate back (only the merge is timed; the map keeps its size). range(1): the
// kept entry considered (EkfConfig::merge_considers_kept). A fixed number of iterations: some ten
// thousand plain merges into one landmark from one pose shrink it until no duplicate can be made.
void BM_MergeDuplicate(benchmark::State& state) {
  auto ekf = make_filter(static_cast<int>(state.range(0)), false, state.range(1) != 0);
  int merged = 0;
  for (auto _ : state) {
    state.PauseTiming();
    int keep = -1;
    const int drop = make_duplicate(*ekf, keep);
    state.ResumeTiming();
    merged += ekf->merge_landmarks(keep, drop, 0.0) == cs::ObservationResult::kFused ? 1 : 0;
  }
  state.counters["state_dim"] = ekf->active_dim();
  state.counters["merged"] = merged;
}
BENCHMARK(BM_MergeDuplicate)
    ->ArgsProduct({{25, 100}, {0, 1}})
    ->ArgNames({"landmarks", "considers_kept"})
    ->Iterations(2000)
    ->Unit(benchmark::kMicrosecond);

// For instruction counts under callgrind (tools/bench/estimator.sh): each op runs `calls` times
// inside a function of its own, which callgrind collects with --toggle-collect.
std::array<cs::Observation, 10> ten_observations(const cs::Ekf& ekf, int& m) {
  std::array<cs::Observation, 10> obs{};
  m = 0;
  for (int slot = 0; slot < hal::kMaxLandmarks && m < 10; ++slot) {
    cs::PixelPrediction p;
    if (ekf.predict_pixel(slot, p) && ekf.camera().in_image(p.uv.x(), p.uv.y())) {
      obs[static_cast<std::size_t>(m++)] = {slot, p.uv.x() + 0.2, p.uv.y() - 0.1};
    }
  }
  return obs;
}

__attribute__((noinline)) void counted_predict(cs::Ekf& ekf, int calls) {
  const cs::OdometryIncrement u = step_increment();
  for (int i = 0; i < calls; ++i) {
    ekf.predict(u);
  }
}

__attribute__((noinline)) void counted_update(cs::Ekf& ekf, const cs::Observation* obs, int m,
                                              int calls) {
  for (int i = 0; i < calls; ++i) {
    ekf.update(obs, m);
  }
}

__attribute__((noinline)) void counted_initialize(cs::Ekf& ekf, int calls) {
  for (int i = 0; i < calls; ++i) {
    ekf.delete_landmark(ekf.initialize_landmark(200.0, 90.0));
  }
}

__attribute__((noinline)) void counted_merge(cs::Ekf& ekf, int keep, int drop) {
  ekf.merge_landmarks(keep, drop, 0.0);
}

int count_instructions(const char* op, int landmarks, int calls) {
  auto ekf = make_filter(landmarks, std::strcmp(op, "update_invariant") == 0,
                         std::strcmp(op, "merge_considered") == 0);
  if (std::strcmp(op, "predict") == 0) {
    counted_predict(*ekf, calls);
  } else if (std::strcmp(op, "update") == 0 || std::strcmp(op, "update_invariant") == 0) {
    int m = 0;
    const auto obs = ten_observations(*ekf, m);
    counted_update(*ekf, obs.data(), m, calls);
  } else if (std::strcmp(op, "initialize") == 0) {
    counted_initialize(*ekf, calls);
  } else if (std::strcmp(op, "merge") == 0 || std::strcmp(op, "merge_considered") == 0) {
    for (int i = 0; i < calls; ++i) {
      int keep = -1;
      const int drop = make_duplicate(*ekf, keep);
      counted_merge(*ekf, keep, drop);
    }
  } else {
    std::fprintf(stderr,
                 "bench_estimator: unknown op '%s' (predict, update, update_invariant, initialize, "
                 "merge, merge_considered)\n",
                 op);
    return 2;
  }
  return 0;
}

}  // namespace

// bench_estimator [google benchmark flags]
// bench_estimator --count OP LANDMARKS CALLS
//   (OP: predict, update, update_invariant, initialize, merge, merge_considered)
int main(int argc, char** argv) {
  if (argc == 5 && std::strcmp(argv[1], "--count") == 0) {
    return count_instructions(argv[2], std::atoi(argv[3]), std::atoi(argv[4]));
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) {
    return 1;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
