#include "cleanslam/slam_core/frontend/landmark_book.hpp"

#include <algorithm>
#include <cstddef>

namespace cleanslam::slam_core::frontend {

namespace {
constexpr std::uint32_t kLongGapFrames = 1000;

bool in_range(int slot) {
  return slot >= 0 && slot < hal::kMaxLandmarks;
}
}  // namespace

void LandmarkBook::activate(int slot) {
  if (!in_range(slot)) {
    return;
  }
  const auto s = static_cast<std::size_t>(slot);
  if (!active_[s]) {
    active_[s] = true;
    ++active_count_;
  }
  failures_[s] = 0;
  matches_[s] = 0;
  last_match_[s] = frame_;
}

void LandmarkBook::resume(int slot) {
  if (!in_range(slot)) {
    return;
  }
  activate(slot);
  const auto s = static_cast<std::size_t>(slot);
  matches_[s] = static_cast<std::uint16_t>(std::max(0, config_.min_matches_to_keep));
  last_match_[s] = frame_ - kLongGapFrames;
}

void LandmarkBook::remove(int slot) {
  if (!in_range(slot)) {
    return;
  }
  const auto s = static_cast<std::size_t>(slot);
  if (active_[s]) {
    active_[s] = false;
    --active_count_;
  }
  failures_[s] = 0;
  matches_[s] = 0;
}

bool LandmarkBook::active(int slot) const {
  return in_range(slot) && active_[static_cast<std::size_t>(slot)];
}

bool LandmarkBook::record(int slot, bool matched) {
  if (!active(slot)) {
    return false;
  }
  const auto s = static_cast<std::size_t>(slot);
  if (matched) {
    failures_[s] = 0;
    if (matches_[s] < UINT16_MAX) {
      ++matches_[s];
    }
    last_match_[s] = frame_;
    return false;
  }
  if (failures_[s] < UINT16_MAX) {
    ++failures_[s];
  }
  return failures_[s] >= config_.max_consecutive_failures;
}

int LandmarkBook::failures(int slot) const {
  return in_range(slot) ? failures_[static_cast<std::size_t>(slot)] : 0;
}

int LandmarkBook::frames_since_match(int slot) const {
  return in_range(slot) ? static_cast<int>(frame_ - last_match_[static_cast<std::size_t>(slot)])
                        : 0;
}

int LandmarkBook::matches(int slot) const {
  return in_range(slot) ? matches_[static_cast<std::size_t>(slot)] : 0;
}

int select_new_corners(const Corner* corners, int corner_count, const double* occupied_u,
                       const double* occupied_v, int occupied_count, double exclusion_px, int width,
                       int height, int margin_px, int max_out, int* out) {
  const double ex2 = exclusion_px * exclusion_px;
  int n = 0;
  for (int i = 0; i < corner_count && n < max_out; ++i) {
    const Corner& c = corners[i];
    if (c.x < margin_px || c.y < margin_px || c.x > width - 1 - margin_px ||
        c.y > height - 1 - margin_px) {
      continue;
    }
    bool free = true;
    for (int j = 0; j < occupied_count && free; ++j) {
      const double du = occupied_u[j] - c.x;
      const double dv = occupied_v[j] - c.y;
      free = du * du + dv * dv >= ex2;
    }
    for (int j = 0; j < n && free; ++j) {
      const double du = corners[out[j]].x - c.x;
      const double dv = corners[out[j]].y - c.y;
      free = du * du + dv * dv >= ex2;
    }
    if (free) {
      out[n++] = i;
    }
  }
  return n;
}

}  // namespace cleanslam::slam_core::frontend
