#pragma once

namespace cleanslam::slam_core::frontend {

// Quantile of the chi-square distribution with an even number of degrees of freedom 2k (the
// joint tests of pixel innovations), from its closed-form CDF 1 - exp(-x/2) sum_{i<k} (x/2)^i/i!.
// Returns 0 for p <= 0 and a non-positive or odd dof; p is clamped below 1 - 1e-12.
[[nodiscard]] double chi2_quantile_even(int dof, double p);

}  // namespace cleanslam::slam_core::frontend
