#include "cleanslam/slam_core/relocalizer.hpp"

#include <algorithm>
#include <cmath>

namespace cleanslam::slam_core {

namespace {
// Patch scales, about a factor 1.25 apart over make_template's range.
constexpr std::array<double, 8> kScaleSteps{0.6, 0.75, 0.95, 1.2, 1.5, 1.9, 2.4, 3.0};
// A corner whose distance the elevation does not give: the scales about 1.
constexpr std::array<int, 3> kUnknownDistanceSteps{1, 2, 3};
constexpr double kMinPairM = 0.3;
constexpr double kMaxRangeM = 15.0;

int nearest_scale_step(double scale) {
  int best = 0;
  for (int k = 1; k < static_cast<int>(kScaleSteps.size()); ++k) {
    if (std::abs(std::log(scale / kScaleSteps[static_cast<std::size_t>(k)])) <
        std::abs(std::log(scale / kScaleSteps[static_cast<std::size_t>(best)]))) {
      best = k;
    }
  }
  return best;
}

// P(X >= k) for X ~ Binomial(n, p).
double binomial_tail(int n, int k, double p) {
  if (k <= 0) {
    return 1.0;
  }
  if (!(p < 1.0)) {
    return k <= n ? 1.0 : 0.0;
  }
  double term = std::pow(1.0 - p, n);  // P(X = 0)
  double below = 0.0;
  for (int i = 0; i < k && i <= n; ++i) {
    below += term;
    term *= static_cast<double>(n - i) / static_cast<double>(i + 1) * p / (1.0 - p);
  }
  return std::clamp(1.0 - below, 0.0, 1.0);
}

// The landmark's distance from the camera at its first sighting: from its anchor (the camera
// then) when the patch has one, else the depth it was first assumed at.
double first_sighting_distance(const Eigen::Vector3d& landmark,
                               const frontend::LandmarkPatch& patch) {
  if (!patch.has_anchor) {
    return patch.first_depth_m;
  }
  return (landmark - Eigen::Vector3d(patch.anchor[0], patch.anchor[1], patch.anchor[2])).norm();
}

bool tried_without_distance(int step) {
  return std::find(kUnknownDistanceSteps.begin(), kUnknownDistanceSteps.end(), step) !=
         kUnknownDistanceSteps.end();
}
}  // namespace

Relocalizer::Relocalizer(const CameraModel& camera, const RelocalizerConfig& config)
    : camera_(camera), config_(config) {}

void Relocalizer::begin(const hal::GrayImageView& image, const frontend::Corner* corners,
                        int corner_count, const Vector6d& camera_pose) {
  image_ = image;
  corners_ = corners;
  corner_count_ = std::clamp(corner_count, 0, hal::kMaxCorners);
  pose_ = camera_pose;
  R_rp_ = rotation_zyx(camera_pose(3), camera_pose(4), 0.0);
  for (int i = 0; i < corner_count_; ++i) {
    LevelRay& ray = rays_[static_cast<std::size_t>(i)];
    ray.valid = false;
    Eigen::Vector2d n;
    if (!camera_.undistort(corners_[i].x, corners_[i].y, n)) {
      continue;
    }
    const Eigen::Vector3d d = R_rp_ * CameraModel::ray(n);
    const double h = std::hypot(d.x(), d.y());
    if (!(h > 0.0)) {
      continue;
    }
    ray.direction = Eigen::Vector2d(d.x(), d.y()) / h;
    ray.tan_elevation = d.z() / h;
    ray.valid = true;
  }
  candidate_count_ = 0;
  added_count_ = 0;
  checked_ = 0;
  confirmed_ = 0;
  check_cursor_ = 0;
  row_ = 0;
  best_score_ = 0;
  second_score_ = 0;
  best_inliers_.fill(false);
}

float Relocalizer::ncc_at(const frontend::PatchTemplate& tmpl, double u, double v) const {
  const int x0 = static_cast<int>(std::lround(u)) - frontend::kPatchRadius;
  const int y0 = static_cast<int>(std::lround(v)) - frontend::kPatchRadius;
  if (x0 < 0 || y0 < 0 || x0 + frontend::kPatchSize > image_.width ||
      y0 + frontend::kPatchSize > image_.height || !(tmpl.sum_sq > 0.0F)) {
    return 0.0F;
  }
  float sum = 0.0F;
  float sum_sq = 0.0F;
  float cross = 0.0F;
  for (int y = 0; y < frontend::kPatchSize; ++y) {
    const std::uint8_t* row = image_.row(y0 + y) + x0;
    for (int x = 0; x < frontend::kPatchSize; ++x) {
      const auto p = static_cast<float>(row[x]);
      sum += p;
      sum_sq += p * p;
      cross += p * tmpl.zero_mean[frontend::pixel_index(y, x, frontend::kPatchSize)];
    }
  }
  constexpr auto kN = static_cast<float>(frontend::kPatchSize * frontend::kPatchSize);
  const float var = sum_sq - sum * sum / kN;
  if (!(var > 0.0F)) {
    return 0.0F;
  }
  return cross / std::sqrt(var * tmpl.sum_sq);
}

bool Relocalizer::level_position(int corner, const Eigen::Vector3d& landmark,
                                 Eigen::Vector2d& q) const {
  const LevelRay& ray = rays_[static_cast<std::size_t>(corner)];
  if (!ray.valid || !(std::abs(ray.tan_elevation) >= config_.min_elevation_tan)) {
    return false;
  }
  const double dist = (landmark.z() - pose_(2)) / ray.tan_elevation;
  if (!(dist > 0.0 && dist < kMaxRangeM)) {
    return false;
  }
  q = ray.direction * dist;
  return true;
}

void Relocalizer::assign_scale_steps(const Eigen::Vector3d& landmark,
                                     const frontend::LandmarkPatch& patch) {
  const double first_distance = first_sighting_distance(landmark, patch);
  const double dz = landmark.z() - pose_(2);
  for (int i = 0; i < corner_count_; ++i) {
    Eigen::Vector2d q;
    scale_step_[static_cast<std::size_t>(i)] =
        level_position(i, landmark, q) ? nearest_scale_step(frontend::predicted_patch_scale(
                                             first_distance, std::sqrt(q.squaredNorm() + dz * dz)))
                                       : -1;
  }
}

void Relocalizer::consider(const Candidate& c) {
  if (candidate_count_ < kMaxCandidates) {
    candidates_[static_cast<std::size_t>(candidate_count_++)] = c;
    return;
  }
  auto worst =
      std::min_element(candidates_.begin(), candidates_.end(),
                       [](const Candidate& a, const Candidate& b) { return a.ncc < b.ncc; });
  if (worst->ncc < c.ncc) {
    *worst = c;
  }
}

void Relocalizer::add_landmark(int slot, const Eigen::Vector3d& position,
                               const frontend::LandmarkPatch& patch) {
  if (added_count_ < hal::kMaxLandmarks) {
    added_[static_cast<std::size_t>(added_count_++)] = Added{slot, position, &patch};
  }
  // The best corners of this landmark, each matched at the scale its distance implies.
  constexpr int kMaxPerLandmark = 8;
  std::array<int, kMaxPerLandmark> best_corner{};
  std::array<float, kMaxPerLandmark> best_ncc{};
  const int keep = std::min(config_.candidates_per_landmark, kMaxPerLandmark);
  int n = 0;
  assign_scale_steps(position, patch);
  for (int step = 0; step < static_cast<int>(kScaleSteps.size()); ++step) {
    const bool without_distance = tried_without_distance(step);
    bool made = false;
    for (int i = 0; i < corner_count_; ++i) {
      const int at_step = scale_step_[static_cast<std::size_t>(i)];
      if (at_step != step && !(at_step < 0 && without_distance)) {
        continue;
      }
      if (!made) {
        made = true;
        if (!frontend::make_template(patch, kScaleSteps[static_cast<std::size_t>(step)], 3.0F,
                                     template_)) {
          break;
        }
      }
      const float ncc = ncc_at(template_, corners_[i].x, corners_[i].y);
      if (!(ncc >= config_.min_ncc)) {
        continue;
      }
      int at = -1;
      for (int k = 0; k < n; ++k) {
        at = best_corner[static_cast<std::size_t>(k)] == i ? k : at;
      }
      if (at < 0 && n < keep) {
        at = n++;
        best_ncc[static_cast<std::size_t>(at)] = -1.0F;
      }
      if (at < 0) {
        at = static_cast<int>(std::min_element(best_ncc.begin(), best_ncc.begin() + n) -
                              best_ncc.begin());
      }
      if (best_ncc[static_cast<std::size_t>(at)] < ncc) {
        best_ncc[static_cast<std::size_t>(at)] = ncc;
        best_corner[static_cast<std::size_t>(at)] = i;
      }
    }
  }
  for (int k = 0; k < n; ++k) {
    Candidate c;
    c.slot = slot;
    c.landmark = position;
    const int i = best_corner[static_cast<std::size_t>(k)];
    c.u_px = corners_[i].x;
    c.v_px = corners_[i].y;
    c.ncc = best_ncc[static_cast<std::size_t>(k)];
    c.has_q = level_position(i, position, c.q);
    consider(c);
  }
}

int Relocalizer::score(double x, double y, double yaw) {
  counted_.fill(false);
  const Eigen::Matrix3d R = rotation_zyx(pose_(3), pose_(4), yaw);
  const Eigen::Vector3d t(x, y, pose_(2));
  const double r2 = config_.inlier_px * config_.inlier_px;
  int inliers = 0;
  for (int k = 0; k < candidate_count_; ++k) {
    const Candidate& c = candidates_[static_cast<std::size_t>(k)];
    if (counted_[static_cast<std::size_t>(c.slot)]) {
      continue;
    }
    Eigen::Vector2d px;
    if (!camera_.project(R.transpose() * (c.landmark - t), px, nullptr)) {
      continue;
    }
    const double du = px.x() - c.u_px;
    const double dv = px.y() - c.v_px;
    if (du * du + dv * dv <= r2) {
      counted_[static_cast<std::size_t>(c.slot)] = true;
      ++inliers;
    }
  }
  return inliers;
}

int Relocalizer::shared_with_best() const {
  int n = 0;
  for (std::size_t s = 0; s < counted_.size(); ++s) {
    n += counted_[s] && best_inliers_[s] ? 1 : 0;
  }
  return n;
}

bool Relocalizer::search_step() {
  const int end = std::min(candidate_count_, row_ + std::max(1, config_.rows_per_step));
  for (; row_ < end; ++row_) {
    const Candidate& a = candidates_[static_cast<std::size_t>(row_)];
    if (!a.has_q) {
      continue;
    }
    for (int j = row_ + 1; j < candidate_count_; ++j) {
      const Candidate& b = candidates_[static_cast<std::size_t>(j)];
      if (!b.has_q || b.slot == a.slot) {
        continue;
      }
      const Eigen::Vector2d mapped = (b.landmark - a.landmark).head<2>();
      const Eigen::Vector2d seen = b.q - a.q;
      const double len = mapped.norm();
      if (len < kMinPairM || std::abs(len - seen.norm()) >
                                 config_.pair_tolerance_m + config_.pair_tolerance_fraction * len) {
        continue;
      }
      const double yaw =
          wrap_angle(std::atan2(mapped.y(), mapped.x()) - std::atan2(seen.y(), seen.x()));
      const Eigen::Rotation2D<double> R(yaw);
      const Eigen::Vector2d xy = 0.5 * ((a.landmark + b.landmark).head<2>() - R * (a.q + b.q));
      const int s = score(xy.x(), xy.y(), yaw);
      if (s <= second_score_) {
        continue;
      }
      // Another pose, not the best one seen again, when most of its inliers are other landmarks.
      const bool other = 2 * shared_with_best() < std::min(s, best_score_);
      if (s > best_score_) {
        if (other) {
          second_score_ = best_score_;
        }
        best_score_ = s;
        best_inliers_ = counted_;
        best_ << xy.x(), xy.y(), pose_(2), pose_(3), pose_(4), yaw;
      } else if (other) {
        second_score_ = s;
      }
    }
  }
  if (row_ < candidate_count_) {
    return false;
  }
  return check_best();
}

bool Relocalizer::check_best() {
  if (best_score_ == 0) {
    return true;
  }
  const Eigen::Matrix3d R = rotation_zyx(best_(3), best_(4), best_(5));
  const Eigen::Vector3d t = best_.head<3>();
  const int r = static_cast<int>(std::ceil(config_.inlier_px));
  const int end = std::min(added_count_, check_cursor_ + std::max(1, config_.landmarks_per_step));
  for (; check_cursor_ < end && checked_ < kMaxChecked; ++check_cursor_) {
    const Added& a = added_[static_cast<std::size_t>(check_cursor_)];
    if (best_inliers_[static_cast<std::size_t>(a.slot)]) {
      continue;
    }
    const Eigen::Vector3d p_c = R.transpose() * (a.position - t);
    Eigen::Vector2d px;
    if (!camera_.project(p_c, px, nullptr) || px.x() < frontend::kPatchRadius + r ||
        px.y() < frontend::kPatchRadius + r ||
        px.x() > image_.width - 1 - frontend::kPatchRadius - r ||
        px.y() > image_.height - 1 - frontend::kPatchRadius - r) {
      continue;
    }
    const double first = first_sighting_distance(a.position, *a.patch);
    if (!frontend::make_template(*a.patch, frontend::predicted_patch_scale(first, p_c.norm()), 3.0F,
                                 template_)) {
      continue;
    }
    ++checked_;
    bool seen = false;
    for (int dy = -r; dy <= r && !seen; ++dy) {
      for (int dx = -r; dx <= r && !seen; ++dx) {
        seen = ncc_at(template_, px.x() + dx, px.y() + dy) >= config_.min_ncc;
      }
    }
    confirmed_ += seen ? 1 : 0;
  }
  return check_cursor_ >= added_count_ || checked_ >= kMaxChecked;
}

bool Relocalizer::found(Vector6d& camera_pose) const {
  const bool checked = checked_ > 0 ? binomial_tail(checked_, confirmed_, config_.chance_match) <=
                                          config_.max_chance_probability
                                    : best_score_ >= config_.min_inliers_unchecked;
  if (best_score_ < config_.min_inliers || best_score_ < second_score_ + config_.min_margin ||
      !checked) {
    return false;
  }
  camera_pose = best_;
  return true;
}

}  // namespace cleanslam::slam_core
