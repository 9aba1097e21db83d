#include "cleanslam/slam_core/frontend/jcbb.hpp"

#include <cmath>

#include "cleanslam/slam_core/frontend/chi_square.hpp"

namespace cleanslam::slam_core::frontend {

namespace {
constexpr std::size_t at(int r, int c, int ld) {
  return static_cast<std::size_t>(r) * static_cast<std::size_t>(ld) + static_cast<std::size_t>(c);
}
}  // namespace

Jcbb::Jcbb(const JcbbConfig& config) : config_(config) {
  bounds_[0] = 0.0;
  for (int k = 1; k <= kMaxObservations; ++k) {
    bounds_[static_cast<std::size_t>(k)] = chi2_quantile_even(2 * k, config_.confidence);
  }
}

// Extends the factor of the `depth` chosen observations by observation `obs`:
// X = L^-1 B, D = S_oo - X^T X = L_oo L_oo^T, y_o = L_oo^-1 (nu_o - X^T y).
bool Jcbb::try_add(int depth, int obs, double nis, double& nis_out) {
  const int n = 2 * depth;
  const int ro = 2 * obs;
  double* L = L_.data();
  // Rows n and n+1 of L hold X^T; B(r, j) = S(2 chosen_r + .., ro + j).
  for (int j = 0; j < 2; ++j) {
    for (int r = 0; r < n; ++r) {
      const int sr = 2 * chosen_[static_cast<std::size_t>(r / 2)] + (r % 2);
      double v = S_[static_cast<std::size_t>((ro + j) * ld_ + sr)];
      for (int c = 0; c < r; ++c) {
        v -= L[at(r, c, kDim)] * L[at(n + j, c, kDim)];
      }
      L[at(n + j, r, kDim)] = v / L[at(r, r, kDim)];
    }
  }
  double d00 = S_[static_cast<std::size_t>(ro * ld_ + ro)];
  double d01 = 0.5 * (S_[static_cast<std::size_t>((ro + 1) * ld_ + ro)] +
                      S_[static_cast<std::size_t>(ro * ld_ + ro + 1)]);
  double d11 = S_[static_cast<std::size_t>((ro + 1) * ld_ + ro + 1)];
  double e0 = nu_[ro];
  double e1 = nu_[ro + 1];
  for (int c = 0; c < n; ++c) {
    const double x0 = L[at(n, c, kDim)];
    const double x1 = L[at(n + 1, c, kDim)];
    d00 -= x0 * x0;
    d01 -= x0 * x1;
    d11 -= x1 * x1;
    e0 -= x0 * y_[static_cast<std::size_t>(c)];
    e1 -= x1 * y_[static_cast<std::size_t>(c)];
  }
  if (!(d00 > 0.0)) {
    return false;
  }
  const double l00 = std::sqrt(d00);
  const double l10 = d01 / l00;
  const double rem = d11 - l10 * l10;
  if (!(rem > 0.0)) {
    return false;
  }
  const double l11 = std::sqrt(rem);
  const double y0 = e0 / l00;
  const double y1 = (e1 - l10 * y0) / l11;
  nis_out = nis + y0 * y0 + y1 * y1;
  if (!(nis_out <= bounds_[static_cast<std::size_t>(depth) + 1])) {
    return false;
  }
  L[at(n, n, kDim)] = l00;
  L[at(n, n + 1, kDim)] = 0.0;
  L[at(n + 1, n, kDim)] = l10;
  L[at(n + 1, n + 1, kDim)] = l11;
  y_[static_cast<std::size_t>(n)] = y0;
  y_[static_cast<std::size_t>(n) + 1] = y1;
  return true;
}

void Jcbb::visit(int next, int depth, double nis) {
  ++nodes_;
  if (next == candidate_count_) {
    if (depth > best_count_ || (depth == best_count_ && nis < best_nis_)) {
      best_count_ = depth;
      best_nis_ = nis;
      for (int i = 0; i < depth; ++i) {
        best_[static_cast<std::size_t>(i)] = chosen_[static_cast<std::size_t>(i)];
      }
    }
    return;
  }
  const int reachable = depth + (candidate_count_ - next);
  // The joint NIS only grows as observations are added, so an equally large set cannot beat a
  // lower one already found.
  if (reachable < best_count_ || (reachable == best_count_ && nis >= best_nis_)) {
    return;
  }
  const int obs = candidates_[static_cast<std::size_t>(next)];
  double nis_with = 0.0;
  if (try_add(depth, obs, nis, nis_with)) {
    chosen_[static_cast<std::size_t>(depth)] = obs;
    visit(next + 1, depth + 1, nis_with);
  }
  visit(next + 1, depth, nis);
}

JcbbResult Jcbb::solve(const double* nu, const double* S, int m, bool* inlier) {
  JcbbResult result;
  if (m <= 0 || m > kMaxObservations || nu == nullptr || S == nullptr || inlier == nullptr) {
    if (inlier != nullptr) {
      for (int i = 0; i < m && i < kMaxObservations; ++i) {
        inlier[i] = false;
      }
    }
    return result;
  }
  nu_ = nu;
  S_ = S;
  ld_ = 2 * m;
  candidate_count_ = 0;
  best_count_ = 0;
  best_nis_ = 0.0;
  nodes_ = 0;
  const double gate = bounds_[1];
  for (int i = 0; i < m; ++i) {
    inlier[i] = false;
    const int r = 2 * i;
    bool finite = std::isfinite(nu[r]) && std::isfinite(nu[r + 1]);
    for (int c = 0; finite && c < ld_; ++c) {
      finite = std::isfinite(S[static_cast<std::size_t>(c * ld_ + r)]) &&
               std::isfinite(S[static_cast<std::size_t>(c * ld_ + r + 1)]);
    }
    double nis = 0.0;
    if (finite && try_add(0, i, 0.0, nis) && nis <= gate) {
      candidates_[static_cast<std::size_t>(candidate_count_++)] = i;
    } else {
      ++result.rejected_individually;
    }
  }
  visit(0, 0, 0.0);
  for (int i = 0; i < best_count_; ++i) {
    inlier[best_[static_cast<std::size_t>(i)]] = true;
  }
  result.inlier_count = best_count_;
  result.joint_nis = best_nis_;
  result.update = best_count_ >= config_.min_inliers;
  result.nodes = nodes_;
  return result;
}

}  // namespace cleanslam::slam_core::frontend
