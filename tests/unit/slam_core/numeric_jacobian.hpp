#pragma once

#include <Eigen/Core>

namespace cleanslam::test {

// Central-difference Jacobian of f: R^N -> R^M at x.
template <int M, int N, typename F>
Eigen::Matrix<double, M, N> numeric_jacobian(const F& f, const Eigen::Matrix<double, N, 1>& x,
                                             double step = 1e-6) {
  Eigen::Matrix<double, M, N> J;
  for (int i = 0; i < N; ++i) {
    Eigen::Matrix<double, N, 1> a = x;
    Eigen::Matrix<double, N, 1> b = x;
    a(i) += step;
    b(i) -= step;
    J.col(i) = (f(a) - f(b)) / (2.0 * step);
  }
  return J;
}

}  // namespace cleanslam::test
