#pragma once

#include <cstddef>
#include <cstdint>

#include "cleanslam/paper_models/comparison_scenario.hpp"
#include "table.hpp"

// The paper's figures (Section 4) as tables in the paper's units (cm).
namespace cleanslam::tools::paper {

struct Fig10Options {
  paper_models::Motion motion = paper_models::Motion::kForward;
  std::size_t hypotheses = 5;
};
Table fig10(const Fig10Options& options);

inline constexpr std::uint32_t kLandmarkSeed = 2012;
Table fig8();
Table fig7();

struct Fig9Options {
  int runs = 50;
  std::uint32_t seed = 1;
};
Table fig9(const Fig9Options& options);

}  // namespace cleanslam::tools::paper
