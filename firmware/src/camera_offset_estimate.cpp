#include "cleanslam/firmware/camera_offset_estimate.hpp"

#include <algorithm>
#include <cmath>

#include "cleanslam/hal/time.hpp"

namespace cleanslam::firmware {

namespace {
constexpr hal::TimeNs kMaxGyroGapNs = 50'000'000;

double candidate_step_s() {
  return 2.0 * CameraOffsetEstimate::kRangeS / (CameraOffsetEstimate::kCandidates - 1);
}

// A record whose pixel is a measurement of its track.
bool measured(hal::log::UpdateStatus s) {
  using S = hal::log::UpdateStatus;
  return s == S::kUpdated || s == S::kGated || s == S::kSkipped || s == S::kDepthBound ||
         s == S::kBehindCamera || s == S::kInitialized;
}
}  // namespace

CameraOffsetEstimate::CameraOffsetEstimate(const hal::CameraCalibration& camera)
    : valid_(camera.fx > 0.0 && camera.fy > 0.0),
      fx_(camera.fx),
      fy_(camera.fy),
      cx_(camera.cx),
      cy_(camera.cy),
      configured_s_(camera.time_offset_s) {
  // T_body_cam's rotation maps camera vectors into the body; its transpose the other way.
  for (std::size_t r = 0; r < 3; ++r) {
    for (std::size_t c = 0; c < 3; ++c) {
      R_cam_body_[3 * r + c] = camera.T_body_cam[4 * c + r];
    }
  }
}

void CameraOffsetEstimate::gyro(const hal::GyroSample& s) {
  Turn next;
  next.t_ns = s.t_ns;
  next.rate = {s.has_xy ? s.wx_rad_s : 0.0, s.has_xy ? s.wy_rad_s : 0.0, s.wz_rad_s};
  if (turn_count_ > 0) {
    const Turn& prev = turns_[static_cast<std::size_t>(newest_)];
    const double dt = hal::to_seconds(s.t_ns - prev.t_ns);
    next.span = s.t_ns - prev.t_ns > kMaxGyroGapNs ? prev.span + 1 : prev.span;
    for (std::size_t i = 0; i < 3; ++i) {
      next.angle[i] = prev.angle[i] + 0.5 * (prev.rate[i] + next.rate[i]) * dt;
    }
  }
  newest_ = (newest_ + 1) % kTurns;
  turns_[static_cast<std::size_t>(newest_)] = next;
  turn_count_ = std::min(turn_count_ + 1, kTurns);
  evaluate_ready_pairs();
}

void CameraOffsetEstimate::evaluate_ready_pairs() {
  const hal::TimeNs latest = hal::from_seconds(configured_s_ + kRangeS);
  const hal::TimeNs gyro_ns = turns_[static_cast<std::size_t>(newest_)].t_ns;
  // A few pairs per gyro sample: a frame's pairs become ready together, and the loop's tick is
  // bounded.
  for (int done = 0; pending_count_ > 0 && done < kPairsPerGyroSample; ++done) {
    const Pair& p = pending_[static_cast<std::size_t>(pending_first_)];
    if (hal::add_saturated(p.b.t_ns, latest) > gyro_ns) {
      return;
    }
    evaluate(p);
    pending_first_ = (pending_first_ + 1) % kPending;
    --pending_count_;
  }
}

const CameraOffsetEstimate::Turn& CameraOffsetEstimate::turn(int k) const {
  return turns_[static_cast<std::size_t>((newest_ - turn_count_ + 1 + k + kTurns) % kTurns)];
}

bool CameraOffsetEstimate::turn_at(hal::TimeNs t_ns, int& k, std::array<double, 3>& angle,
                                   std::uint64_t& span) const {
  if (turn_count_ < 2 || t_ns < turn(0).t_ns || t_ns > turn(turn_count_ - 1).t_ns) {
    return false;
  }
  if (k < 0 || turn(k).t_ns > t_ns) {  // no usable hint: bisect
    int lo = 0;
    int hi = turn_count_ - 1;
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      (turn(mid).t_ns <= t_ns ? lo : hi) = mid;
    }
    k = lo;
  }
  while (k + 2 < turn_count_ && turn(k + 1).t_ns <= t_ns) {
    ++k;
  }
  const Turn& a = turn(k);
  const Turn& b = turn(std::min(k + 1, turn_count_ - 1));
  if (b.t_ns - a.t_ns > kMaxGyroGapNs) {
    return false;
  }
  span = a.span;
  const double f = b.t_ns > a.t_ns
                       ? static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns)
                       : 0.0;
  for (std::size_t i = 0; i < 3; ++i) {
    angle[i] = a.angle[i] + f * (b.angle[i] - a.angle[i]);
  }
  return true;
}

void CameraOffsetEstimate::update(const hal::log::UpdateRecord& r) {
  if (!valid_) {
    return;
  }
  if (r.t_ns != current_t_ns_) {  // a new frame: the previous one's points are what it pairs with
    const bool consecutive =
        current_t_ns_ >= 0 && r.t_ns > current_t_ns_ && r.t_ns - current_t_ns_ <= kMaxFrameGapNs;
    last_ = current_;
    last_count_ = consecutive ? current_count_ : 0;
    current_count_ = 0;
    current_t_ns_ = r.t_ns;
  }
  if (!measured(r.status) || r.track_id < 0 || !std::isfinite(r.u_px) || !std::isfinite(r.v_px)) {
    return;
  }
  if (r.status != hal::log::UpdateStatus::kInitialized) {  // else a new point in that slot
    for (int i = 0; i < last_count_; ++i) {
      if (last_[static_cast<std::size_t>(i)].track == r.track_id) {
        if (pending_count_ == kPending) {  // the gyro stopped: the oldest waiting pair goes
          pending_first_ = (pending_first_ + 1) % kPending;
          --pending_count_;
        }
        pending_[static_cast<std::size_t>((pending_first_ + pending_count_++) % kPending)] =
            Pair{last_[static_cast<std::size_t>(i)], Point{r.track_id, r.t_ns, r.u_px, r.v_px}};
        break;
      }
    }
  }
  if (current_count_ < kPoints) {
    current_[static_cast<std::size_t>(current_count_++)] =
        Point{r.track_id, r.t_ns, r.u_px, r.v_px};
  }
}

void CameraOffsetEstimate::evaluate(const Pair& p) {
  const Point& a = p.a;
  const Point& b = p.b;
  // Small-angle image motion of a static point under the camera's turn, at the pair's midpoint.
  const double x = (0.5 * (a.u + b.u) - cx_) / fx_;
  const double y = (0.5 * (a.v + b.v) - cy_) / fy_;
  const double du = b.u - a.u;
  const double dv = b.v - a.v;
  std::array<double, kCandidates> err{};
  int ka = -1;  // the candidates' instants ascend: each lookup starts where the last ended
  int kb = -1;
  for (int j = 0; j < kCandidates; ++j) {
    const double d = configured_s_ - kRangeS + j * candidate_step_s();
    std::array<double, 3> ta{};
    std::array<double, 3> tb{};
    std::uint64_t span_a = 0;
    std::uint64_t span_b = 0;
    if (!turn_at(hal::add_saturated(a.t_ns, hal::from_seconds(d)), ka, ta, span_a) ||
        !turn_at(hal::add_saturated(b.t_ns, hal::from_seconds(d)), kb, tb, span_b) ||
        span_a != span_b) {
      return;
    }
    std::array<double, 3> w{};  // the camera's turn, in its own frame
    for (std::size_t i = 0; i < 3; ++i) {
      w[i] = R_cam_body_[3 * i] * (tb[0] - ta[0]) + R_cam_body_[3 * i + 1] * (tb[1] - ta[1]) +
             R_cam_body_[3 * i + 2] * (tb[2] - ta[2]);
    }
    const double pu = fx_ * (x * y * w[0] - (1.0 + x * x) * w[1] + y * w[2]);
    const double pv = fy_ * ((1.0 + y * y) * w[0] - x * y * w[1] - x * w[2]);
    const double e2 = (du - pu) * (du - pu) + (dv - pv) * (dv - pv);
    err[static_cast<std::size_t>(j)] = std::min(e2, kMaxPairErrorPx * kMaxPairErrorPx);
  }
  for (std::size_t j = 0; j < err.size(); ++j) {
    sse_[j] += err[j];
  }
  ++pairs_;
}

CameraOffsetEstimate::Result CameraOffsetEstimate::result() const {
  Result out;
  out.configured_s = configured_s_;
  out.pairs = pairs_;
  if (pairs_ < kMinPairs) {
    return out;
  }
  const auto best = static_cast<int>(std::min_element(sse_.begin(), sse_.end()) - sse_.begin());
  if (best == 0 || best == kCandidates - 1) {  // at the edge of the range: no minimum inside
    return out;
  }
  const auto j = static_cast<std::size_t>(best);
  const double h = candidate_step_s();
  const double denominator = sse_[j - 1] - 2.0 * sse_[j] + sse_[j + 1];
  const double shift = denominator > 0.0 ? 0.5 * (sse_[j - 1] - sse_[j + 1]) / denominator : 0.0;
  out.suggested_s = configured_s_ - kRangeS + (best + shift) * h;
  // The interval where the sum rises by less than one residual variance (chi-square, 1 dof):
  // its half-width is the std. dev.; it reaches the range's edge when the data cannot tell.
  const double rise = sse_[j] + sse_[j] / static_cast<double>(2 * pairs_ - 1);
  std::size_t lo = j;
  std::size_t hi = j;
  while (lo > 0 && sse_[lo - 1] <= rise) {
    --lo;
  }
  while (hi + 1 < sse_.size() && sse_[hi + 1] <= rise) {
    ++hi;
  }
  if (lo == 0 || hi + 1 == sse_.size()) {
    return out;
  }
  const auto crossing = [&](std::size_t inside, std::size_t outside) {
    const double f = (rise - sse_[inside]) / (sse_[outside] - sse_[inside]);
    return static_cast<double>(inside) +
           f * (static_cast<double>(outside) - static_cast<double>(inside));
  };
  out.std_s = 0.5 * (crossing(hi, hi + 1) - crossing(lo, lo - 1)) * h;
  out.measurable = std::isfinite(out.suggested_s) && out.std_s < kMaxStdS;
  return out;
}

}  // namespace cleanslam::firmware
