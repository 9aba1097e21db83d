#include "cleanslam/slam_core/frontend/tracker.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace cleanslam::slam_core::frontend {

namespace {

constexpr int kN = kPatchSize * kPatchSize;

// One pass over the 15x15 window centred on (u, v), sampled bilinearly (translation only: one
// set of weights for all pixels), gathering the sums the Lucas-Kanade step and the NCC need.
struct WindowSums {
  float s1 = 0.0F;   // sum w
  float s2 = 0.0F;   // sum w^2
  float sgx = 0.0F;  // sum gx w
  float sgy = 0.0F;  // sum gy w
  float swt = 0.0F;  // sum w t
};

bool window_sums(const hal::GrayImageView& image, const PatchTemplate& tmpl, double u, double v,
                 WindowSums& out) {
  if (!(u >= kPatchRadius) || !(v >= kPatchRadius)) {
    return false;
  }
  const double fu = std::floor(u);
  const double fv = std::floor(v);
  const int ix = static_cast<int>(fu) - kPatchRadius;
  const int iy = static_cast<int>(fv) - kPatchRadius;
  if (ix + kPatchSize >= image.width || iy + kPatchSize >= image.height) {
    return false;
  }
  const auto ax = static_cast<float>(u - fu);
  const auto ay = static_cast<float>(v - fv);
  const float w00 = (1.0F - ax) * (1.0F - ay);
  const float w01 = ax * (1.0F - ay);
  const float w10 = (1.0F - ax) * ay;
  const float w11 = ax * ay;
  // Centred on mid-gray so that the float sums of squares keep their precision.
  constexpr float kBias = 128.0F;
  float s1 = 0.0F;
  float s2 = 0.0F;
  float sgx = 0.0F;
  float sgy = 0.0F;
  float swt = 0.0F;
  for (int r = 0; r < kPatchSize; ++r) {
    const std::uint8_t* a = image.row(iy + r) + ix;
    const std::uint8_t* b = a + image.stride;
    const std::size_t row = pixel_index(r, 0, kPatchSize);
    const float* gx = tmpl.gx.data() + row;
    const float* gy = tmpl.gy.data() + row;
    const float* t = tmpl.zero_mean.data() + row;
    for (int c = 0; c < kPatchSize; ++c) {
      const float w = w00 * static_cast<float>(a[c]) + w01 * static_cast<float>(a[c + 1]) +
                      w10 * static_cast<float>(b[c]) + w11 * static_cast<float>(b[c + 1]) - kBias;
      s1 += w;
      s2 += w * w;
      sgx += gx[c] * w;
      sgy += gy[c] * w;
      swt += t[c] * w;
    }
  }
  out = {s1, s2, sgx, sgy, swt};
  return true;
}

// NCC between the template and the window centred on (u, v); 0 where no window fits or it is
// flat.
float window_ncc(const hal::GrayImageView& image, const PatchTemplate& tmpl, double u, double v) {
  WindowSums ws;
  if (!window_sums(image, tmpl, u, v, ws)) {
    return 0.0F;
  }
  const float ss = ws.s2 - ws.s1 * ws.s1 / static_cast<float>(kN);
  if (!(ss > 0.0F)) {
    return 0.0F;
  }
  return (ws.swt - ws.s1 / static_cast<float>(kN) * tmpl.sum_t) / std::sqrt(ss * tmpl.sum_sq);
}

}  // namespace

Refinement Tracker::refine(const hal::GrayImageView& image, const PatchTemplate& tmpl, double u_px,
                           double v_px) const {
  Refinement out;
  if (!tmpl.valid) {
    return out;
  }
  const float min_ss = config_.min_window_std * config_.min_window_std * static_cast<float>(kN);
  const double max_travel2 =
      static_cast<double>(config_.max_travel_px) * static_cast<double>(config_.max_travel_px);
  const double eps2 =
      static_cast<double>(config_.convergence_px) * static_cast<double>(config_.convergence_px);
  double u = u_px;
  double v = v_px;
  bool converged = false;
  double last_step2 = 0.0;
  float ncc = 0.0F;
  int it = 0;
  WindowSums ws;
  while (it < config_.max_iterations) {
    ++it;
    if (!window_sums(image, tmpl, u, v, ws)) {
      out.iterations = it;
      return out;
    }
    const float mean = ws.s1 / static_cast<float>(kN);
    const float ss = ws.s2 - ws.s1 * mean;
    if (!(ss > min_ss)) {
      out.iterations = it;
      return out;
    }
    // NCC at this iterate: sum (w - mean) t / sqrt(ss_w ss_t).
    ncc = (ws.swt - mean * tmpl.sum_t) / std::sqrt(ss * tmpl.sum_sq);
    // Zero-mean residual with the window's contrast matched to the template's:
    // e = (w - mean) / g - t, g = sqrt(ss_w / ss_t); b = sum grad(T) e.
    const float inv_g = std::sqrt(tmpl.sum_sq / ss);
    const float bx = (ws.sgx - mean * tmpl.sum_gx) * inv_g - tmpl.sum_gx_t;
    const float by = (ws.sgy - mean * tmpl.sum_gy) * inv_g - tmpl.sum_gy_t;
    const auto dx = static_cast<double>(tmpl.h_inv_xx * bx + tmpl.h_inv_xy * by);
    const auto dy = static_cast<double>(tmpl.h_inv_xy * bx + tmpl.h_inv_yy * by);
    // Inverse compositional update of a translation: p <- p - dp.
    u -= dx;
    v -= dy;
    const double tu = u - u_px;
    const double tv = v - v_px;
    if (!std::isfinite(u) || !std::isfinite(v) || tu * tu + tv * tv > max_travel2) {
      out.iterations = it;
      return out;
    }
    last_step2 = dx * dx + dy * dy;
    if (last_step2 < eps2) {
      converged = true;
      break;
    }
  }
  out.iterations = it;
  out.u_px = u;
  out.v_px = v;
  // The NCC of the last iterate, at most the last (sub-threshold) step away. A run that used all
  // its iterations still counts when it settled to within a tenth of a pixel.
  out.ncc = ncc;
  out.converged = converged || last_step2 < 0.01;
  return out;
}

TrackResult Tracker::track(const hal::GrayImageView& image, const PatchTemplate& tmpl,
                           const SearchRegion& region, const Corner* corners, int corner_count,
                           bool reacquire) const {
  TrackResult result;
  if (!region.valid) {
    result.failure = TrackFailure::kNoRegion;
    return result;
  }
  if (!tmpl.valid || tmpl.isotropy < config_.min_template_isotropy) {
    result.failure = TrackFailure::kNoTemplate;
    return result;
  }
  // Where look-alikes are looked for: the region's box, for a reacquisition at least
  // reacquire_box_px around the prediction.
  const double grow = reacquire ? static_cast<double>(config_.reacquire_box_px) : 0.0;
  const double bx0 = std::min(region.x_min, region.center.x() - grow);
  const double bx1 = std::max(region.x_max, region.center.x() + grow);
  const double by0 = std::min(region.y_min, region.center.y() - grow);
  const double by1 = std::max(region.y_max, region.center.y() + grow);
  const auto in_box = [&](double x, double y) {
    return x >= bx0 && x <= bx1 && y >= by0 && y <= by1;
  };
  const float min_ncc = reacquire ? config_.reacquire_min_ncc : config_.min_ncc;
  // Start points: the prediction (clamped into the searchable box), then the corners inside the
  // gate whose window already resembles the template most (NCC at the corner, one pass each;
  // among the nearest kMaxCandidates when the gate holds more).
  constexpr int kMaxCandidates = 32;
  std::array<double, kMaxCandidates> cu{};
  std::array<double, kMaxCandidates> cv{};
  std::array<double, kMaxCandidates> cm{};
  int nc = 0;
  for (int i = 0; i < corner_count; ++i) {
    const double x = corners[i].x;
    const double y = corners[i].y;
    if (!in_box(x, y)) {
      continue;
    }
    // Corners of the box outside the gate are candidates too: not to be accepted, but a
    // look-alike there makes the match ambiguous.
    const double m2 = region.mahalanobis2(x, y);
    int pos = nc;
    if (nc == kMaxCandidates) {
      if (m2 >= cm[kMaxCandidates - 1]) {
        continue;
      }
      pos = nc - 1;
    } else {
      ++nc;
    }
    for (; pos > 0 && cm[static_cast<std::size_t>(pos - 1)] > m2; --pos) {
      cu[static_cast<std::size_t>(pos)] = cu[static_cast<std::size_t>(pos - 1)];
      cv[static_cast<std::size_t>(pos)] = cv[static_cast<std::size_t>(pos - 1)];
      cm[static_cast<std::size_t>(pos)] = cm[static_cast<std::size_t>(pos - 1)];
    }
    cu[static_cast<std::size_t>(pos)] = x;
    cv[static_cast<std::size_t>(pos)] = y;
    cm[static_cast<std::size_t>(pos)] = m2;
  }
  constexpr int kMaxStarts = 16;
  std::array<double, kMaxStarts> su{};
  std::array<double, kMaxStarts> sv{};
  std::array<float, kMaxStarts> sn{};
  su[0] = std::clamp(region.center.x(), region.x_min, region.x_max);
  sv[0] = std::clamp(region.center.y(), region.y_min, region.y_max);
  int n = 1;
  const int max_starts = std::clamp(config_.max_corner_starts + 1, 1, kMaxStarts);
  for (int i = 0; i < nc; ++i) {
    const float ncc =
        window_ncc(image, tmpl, cu[static_cast<std::size_t>(i)], cv[static_cast<std::size_t>(i)]);
    if (!(ncc > config_.min_start_ncc)) {
      continue;
    }
    // Keep the most similar, sorted by insertion (ties: the nearer, listed first).
    int pos = n;
    if (n == max_starts) {
      if (ncc <= sn[static_cast<std::size_t>(n - 1)]) {
        continue;
      }
      pos = n - 1;
    } else {
      ++n;
    }
    for (; pos > 1 && sn[static_cast<std::size_t>(pos - 1)] < ncc; --pos) {
      su[static_cast<std::size_t>(pos)] = su[static_cast<std::size_t>(pos - 1)];
      sv[static_cast<std::size_t>(pos)] = sv[static_cast<std::size_t>(pos - 1)];
      sn[static_cast<std::size_t>(pos)] = sn[static_cast<std::size_t>(pos - 1)];
    }
    su[static_cast<std::size_t>(pos)] = cu[static_cast<std::size_t>(i)];
    sv[static_cast<std::size_t>(pos)] = cv[static_cast<std::size_t>(i)];
    sn[static_cast<std::size_t>(pos)] = ncc;
  }

  // Every converged run inside the gate is a candidate.
  std::array<Refinement, kMaxStarts> cand{};
  std::array<double, kMaxStarts> cand_m2{};
  int ncand = 0;
  for (int i = 0; i < n; ++i) {
    const double u0 = su[static_cast<std::size_t>(i)];
    const double v0 = sv[static_cast<std::size_t>(i)];
    // A start next to a point a previous run converged to would converge there again.
    bool repeat = false;
    for (int j = 0; j < ncand && !repeat; ++j) {
      const double du = cand[static_cast<std::size_t>(j)].u_px - u0;
      const double dv = cand[static_cast<std::size_t>(j)].v_px - v0;
      repeat = du * du + dv * dv < 0.5;
    }
    if (repeat) {
      continue;
    }
    const Refinement r = refine(image, tmpl, u0, v0);
    ++result.starts_tried;
    result.iterations += r.iterations;
    if (!r.converged || !in_box(r.u_px, r.v_px)) {
      continue;
    }
    cand[static_cast<std::size_t>(ncand)] = r;
    cand_m2[static_cast<std::size_t>(ncand)] = region.mahalanobis2(r.u_px, r.v_px);
    ++ncand;
  }
  // The best inside the gate.
  int best = -1;
  for (int i = 0; i < ncand; ++i) {
    if (cand_m2[static_cast<std::size_t>(i)] > region.gate_chi2 ||
        !region.in_box(cand[static_cast<std::size_t>(i)].u_px,
                       cand[static_cast<std::size_t>(i)].v_px)) {
      continue;
    }
    if (best < 0) {
      best = i;
      continue;
    }
    const float ni = cand[static_cast<std::size_t>(i)].ncc;
    const float nb = cand[static_cast<std::size_t>(best)].ncc;
    if (ni > nb + config_.ncc_tie ||
        (ni > nb - config_.ncc_tie &&
         cand_m2[static_cast<std::size_t>(i)] < cand_m2[static_cast<std::size_t>(best)])) {
      best = i;
    }
  }
  if (best < 0) {
    result.failure = TrackFailure::kNoConvergence;
    return result;
  }
  const Refinement& b = cand[static_cast<std::size_t>(best)];
  result.u_px = b.u_px;
  result.v_px = b.v_px;
  result.ncc = b.ncc;
  if (b.ncc < min_ncc) {
    result.failure = TrackFailure::kLowNcc;
    return result;
  }
  // Repetitive texture: another place in the search box that matches about as well.
  const double distinct2 =
      static_cast<double>(config_.distinct_px) * static_cast<double>(config_.distinct_px);
  for (int i = 0; i < ncand; ++i) {
    const Refinement& c = cand[static_cast<std::size_t>(i)];
    const double du = c.u_px - b.u_px;
    const double dv = c.v_px - b.v_px;
    if (du * du + dv * dv > distinct2 && c.ncc > b.ncc - config_.ambiguity_ncc) {
      result.failure = TrackFailure::kAmbiguous;
      return result;
    }
  }
  result.found = true;
  return result;
}

}  // namespace cleanslam::slam_core::frontend
