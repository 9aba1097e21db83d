#include "cleanslam/slam_core/frontend/chi_square.hpp"

#include <algorithm>
#include <cmath>

namespace cleanslam::slam_core::frontend {

namespace {

double chi2_cdf_even(int k, double x) {
  const double h = 0.5 * x;
  double term = 1.0;
  double sum = 1.0;
  for (int i = 1; i < k; ++i) {
    term *= h / i;
    sum += term;
  }
  return 1.0 - std::exp(-h) * sum;
}

}  // namespace

double chi2_quantile_even(int dof, double p) {
  if (dof <= 0 || dof % 2 != 0 || !(p > 0.0)) {
    return 0.0;
  }
  const double q = std::min(p, 1.0 - 1e-12);
  const int k = dof / 2;
  double lo = 0.0;
  double hi = dof + 20.0 * std::sqrt(2.0 * dof) + 60.0;
  for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (chi2_cdf_even(k, mid) < q) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace cleanslam::slam_core::frontend
