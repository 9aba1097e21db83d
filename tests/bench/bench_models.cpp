// One initialization plus one update of the Fig. 10 landmark with each comparison model.
#include <benchmark/benchmark.h>

#include <memory>

#include "cleanslam/paper_models/comparison_scenario.hpp"
#include "cleanslam/paper_models/conventional_model.hpp"
#include "cleanslam/paper_models/inverse_depth_model.hpp"
#include "cleanslam/paper_models/multi_hypothesis_model.hpp"
#include "cleanslam/paper_models/proposed_model.hpp"
#include "cleanslam/slam_core/ekf.hpp"

namespace {

namespace m = cleanslam::paper_models;

const m::Pinhole kCamera{};

template <typename Model, typename Params>
void one_step(benchmark::State& state, const Params& params) {
  const m::ComparisonSetup s = m::fig10_setup(m::Motion::kForward, 12.0);
  for (auto _ : state) {
    Model model(params);
    const m::OneStepResult r = m::one_step(model, kCamera, s.first, s.second, s.landmark);
    benchmark::DoNotOptimize(r.error);
  }
}

void BM_Conventional(benchmark::State& state) {
  one_step<m::ConventionalModel>(state, m::ConventionalParams{kCamera, 10.0, 1000.0, 0.005, 0.1});
}
BENCHMARK(BM_Conventional);

void BM_InverseDepth(benchmark::State& state) {
  one_step<m::InverseDepthModel>(state, m::InverseDepthParams{kCamera, 0.1, 0.5, 0.1, 0.1});
}
BENCHMARK(BM_InverseDepth);

void BM_MultiHypothesis(benchmark::State& state) {
  one_step<m::MultiHypothesisModel>(
      state, m::MultiHypothesisParams{kCamera, static_cast<std::size_t>(state.range(0)), 1.0, 30.0,
                                      0.1, 1e-4});
}
BENCHMARK(BM_MultiHypothesis)->Arg(5)->Arg(20);

void BM_ProposedThroughEkf(benchmark::State& state) {
  const m::ProposedParams params{kCamera, 1000.0, 0.005, 10.0, 1e12};
  const auto ekf = std::make_unique<cleanslam::slam_core::Ekf>(m::pinhole_calibration(kCamera),
                                                               m::proposed_config(params));
  const m::ComparisonSetup s = m::fig10_setup(m::Motion::kForward, 12.0);
  for (auto _ : state) {
    m::ProposedModel model(*ekf);
    const m::OneStepResult r = m::one_step(model, kCamera, s.first, s.second, s.landmark);
    benchmark::DoNotOptimize(r.error);
  }
}
BENCHMARK(BM_ProposedThroughEkf);

}  // namespace

BENCHMARK_MAIN();
