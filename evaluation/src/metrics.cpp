#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "cleanslam/evaluation/evaluation.hpp"

namespace cleanslam::evaluation {
namespace {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
// Two-sided 95% bounds of the chi-square distribution with 3 degrees of freedom.
constexpr double kChi2Low = 0.2158;
constexpr double kChi2High = 9.3484;

Isometry3d to_iso(const std::array<double, 3>& p, const std::array<double, 4>& q) {
  Isometry3d t = Isometry3d::Identity();
  t.linear() = Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
  t.translation() = Vector3d(p[0], p[1], p[2]);
  return t;
}

double angle_of(const Matrix3d& r) {
  const double c = std::clamp(0.5 * (r.trace() - 1.0), -1.0, 1.0);
  return std::acos(c);
}

const char* name_of(Alignment a) {
  switch (a) {
    case Alignment::kNone:
      return "none";
    case Alignment::kSe2:
      return "se2";
    case Alignment::kSe3:
      return "se3";
  }
  return "?";
}

// Poses' NEES values in a row are correlated (an error persists over many poses), so N of them
// carry the information of fewer independent ones: N divided by the integrated autocorrelation
// time, summed by Geyer's initial positive sequence (pairs of lags while their sum stays
// positive). A series without variance counts as one.
double effective_count(const std::vector<double>& x) {
  const std::size_t n = x.size();
  if (n < 2) {
    return static_cast<double>(n);
  }
  double mean = 0.0;
  for (double v : x) {
    mean += v;
  }
  mean /= static_cast<double>(n);
  const auto autocov = [&](std::size_t k) {
    double c = 0.0;
    for (std::size_t i = 0; i + k < n; ++i) {
      c += (x[i] - mean) * (x[i + k] - mean);
    }
    return c / static_cast<double>(n);
  };
  const double c0 = autocov(0);
  if (!(c0 > 0.0)) {
    return 1.0;
  }
  double tau = -1.0;
  for (std::size_t m = 0; 2 * m + 1 < n; ++m) {
    const double pair = (autocov(2 * m) + autocov(2 * m + 1)) / c0;
    if (!(pair > 0.0)) {
      break;
    }
    tau += 2.0 * pair;
  }
  return std::clamp(static_cast<double>(n) / std::max(tau, 1.0), 1.0, static_cast<double>(n));
}

}  // namespace

std::optional<TumPose> interpolate(const std::vector<readers::GroundTruthPose>& gt, hal::TimeNs t) {
  if (gt.empty() || t < gt.front().t_ns || t > gt.back().t_ns) {
    return std::nullopt;
  }
  auto it =
      std::upper_bound(gt.begin(), gt.end(), t,
                       [](hal::TimeNs v, const readers::GroundTruthPose& g) { return v < g.t_ns; });
  const readers::GroundTruthPose& a = *(it - 1);
  TumPose out;
  out.t_ns = t;
  if (it == gt.end() || a.t_ns == t) {
    out.position = a.position_m;
    out.orientation_wxyz = a.orientation_wxyz;
    return out;
  }
  const readers::GroundTruthPose& b = *it;
  const double s = static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  for (std::size_t i = 0; i < 3; ++i) {
    out.position[i] = (1.0 - s) * a.position_m[i] + s * b.position_m[i];
  }
  const Quaterniond qa(a.orientation_wxyz[0], a.orientation_wxyz[1], a.orientation_wxyz[2],
                       a.orientation_wxyz[3]);
  const Quaterniond qb(b.orientation_wxyz[0], b.orientation_wxyz[1], b.orientation_wxyz[2],
                       b.orientation_wxyz[3]);
  const Quaterniond q = qa.slerp(s, qb).normalized();
  out.orientation_wxyz = {q.w(), q.x(), q.y(), q.z()};
  return out;
}

readers::Result<Metrics> evaluate(const std::vector<readers::GroundTruthPose>& groundtruth,
                                  const std::vector<TumPose>& estimate, Alignment alignment) {
  using R = readers::Result<Metrics>;
  Metrics m;
  std::vector<Isometry3d> est, gt;
  std::vector<const TumPose*> src;
  for (const TumPose& e : estimate) {
    const auto g = interpolate(groundtruth, e.t_ns);
    if (!g) {
      ++m.poses_outside_groundtruth;
      continue;
    }
    est.push_back(to_iso(e.position, e.orientation_wxyz));
    gt.push_back(to_iso(g->position, g->orientation_wxyz));
    src.push_back(&e);
  }
  const std::size_t n = est.size();
  if (n == 0) {
    return R::failure("no estimated pose lies within the ground truth's time span");
  }
  m.poses_evaluated = static_cast<int>(n);

  // Alignment: est_aligned = A * est (gt expressed in its own first frame for `none`).
  Isometry3d a = Isometry3d::Identity();
  if (alignment == Alignment::kNone) {
    a = est.front().inverse();
    const Isometry3d g0inv = gt.front().inverse();
    for (auto& g : gt) {
      g = g0inv * g;
    }
  } else {
    Vector3d me = Vector3d::Zero(), mg = Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      me += est[i].translation();
      mg += gt[i].translation();
    }
    me /= static_cast<double>(n);
    mg /= static_cast<double>(n);
    Matrix3d r = Matrix3d::Identity();
    if (alignment == Alignment::kSe3) {
      Matrix3d h = Matrix3d::Zero();
      for (std::size_t i = 0; i < n; ++i) {
        h += (est[i].translation() - me) * (gt[i].translation() - mg).transpose();
      }
      Eigen::JacobiSVD<Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
      const Matrix3d u = svd.matrixU(), v = svd.matrixV();
      Matrix3d d = Matrix3d::Identity();
      d(2, 2) = (v * u.transpose()).determinant() < 0.0 ? -1.0 : 1.0;
      r = v * d * u.transpose();
    } else {
      double sc = 0.0, ss = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const Vector3d e = est[i].translation() - me;
        const Vector3d g = gt[i].translation() - mg;
        sc += e.x() * g.x() + e.y() * g.y();
        ss += e.x() * g.y() - e.y() * g.x();
      }
      const double yaw = (sc == 0.0 && ss == 0.0) ? 0.0 : std::atan2(ss, sc);
      r = Eigen::AngleAxisd(yaw, Vector3d::UnitZ()).toRotationMatrix();
      me.z() = 0.0;
      mg.z() = 0.0;
    }
    a.linear() = r;
    a.translation() = mg - r * me;
  }
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      m.rotation[3 * i + j] =
          a.linear()(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
    }
    m.translation[i] = a.translation()(static_cast<Eigen::Index>(i));
  }

  double sum2 = 0.0, rot2 = 0.0, nees_sum = 0.0;
  int nees_in = 0;
  std::vector<double> nees_series;
  for (std::size_t i = 0; i < n; ++i) {
    const Isometry3d e = a * est[i];
    const Vector3d err = e.translation() - gt[i].translation();
    const double d = err.norm();
    sum2 += d * d;
    m.ate_max_m = std::max(m.ate_max_m, d);
    const double ang = angle_of(gt[i].linear().transpose() * e.linear());
    rot2 += ang * ang;
    if (i == n - 1) {
      m.final_error_m = d;
    }
    if (i > 0) {
      m.path_length_m += (gt[i].translation() - gt[i - 1].translation()).norm();
    }
    if (src[i]->position_covariance) {
      Matrix3d p;
      for (Eigen::Index r = 0; r < 3; ++r) {
        for (Eigen::Index c = 0; c < 3; ++c) {
          p(r, c) = (*src[i]->position_covariance)[static_cast<std::size_t>(3 * r + c)];
        }
      }
      p = a.linear() * (0.5 * (p + p.transpose())) * a.linear().transpose();
      Eigen::LLT<Matrix3d> llt(p);
      if (llt.info() == Eigen::Success) {
        const double nees = err.dot(llt.solve(err));
        nees_sum += nees;
        nees_series.push_back(nees);
        ++m.nees_count;
        if (nees >= kChi2Low && nees <= kChi2High) {
          ++nees_in;
        }
      } else if (m.nees_not_positive_definite++ == 0) {
        m.first_not_positive_definite_s = hal::to_seconds(src[i]->t_ns);
      }
    }
  }
  m.ate_rmse_m = std::sqrt(sum2 / static_cast<double>(n));
  m.orientation_rmse_deg = std::sqrt(rot2 / static_cast<double>(n)) * kRadToDeg;
  if (m.nees_count > 0) {
    m.nees_mean = nees_sum / m.nees_count;
    m.nees_fraction_in_95 = static_cast<double>(nees_in) / m.nees_count;
    m.nees_ratio = m.nees_mean / 3.0;
    m.nees_effective_count = effective_count(nees_series);
    const double k = 3.0 * m.nees_effective_count;
    const double c = 1.0 - 2.0 / (9.0 * k);
    const double w = 1.959964 * std::sqrt(2.0 / (9.0 * k));
    m.nees_ratio_low = std::pow(std::max(0.0, c - w), 3);
    m.nees_ratio_high = std::pow(c + w, 3);
  }

  // RPE over 1 m of ground-truth travel.
  std::vector<double> s(n, 0.0);
  for (std::size_t i = 1; i < n; ++i) {
    s[i] = s[i - 1] + (gt[i].translation() - gt[i - 1].translation()).norm();
  }
  double rt2 = 0.0, rr2 = 0.0;
  std::size_t j = 0;
  for (std::size_t i = 0; i < n; ++i) {
    j = std::max(j, i + 1);
    while (j < n && s[j] - s[i] < 1.0) {
      ++j;
    }
    if (j >= n) {
      break;
    }
    const double dist = s[j] - s[i];
    const Isometry3d dg = gt[i].inverse() * gt[j];
    const Isometry3d de = est[i].inverse() * est[j];
    const double et = (de.translation() - dg.translation()).norm() / dist;
    const double er = angle_of(dg.linear().transpose() * de.linear()) * kRadToDeg / dist;
    rt2 += et * et;
    rr2 += er * er;
    ++m.rpe_pairs;
  }
  if (m.rpe_pairs > 0) {
    m.rpe_translation_per_m = std::sqrt(rt2 / m.rpe_pairs);
    m.rpe_rotation_deg_per_m = std::sqrt(rr2 / m.rpe_pairs);
  }
  return m;
}

const char* nees_verdict(const Metrics& m) {
  if (m.nees_count == 0) {
    return "";
  }
  if (m.nees_ratio > m.nees_ratio_high) {
    return "overconfident";
  }
  return m.nees_ratio < m.nees_ratio_low ? "conservative" : "consistent";
}

std::string to_json(const Metrics& m, Alignment alignment) {
  char verdict[32] = "null";
  if (m.nees_count > 0) {
    std::snprintf(verdict, sizeof(verdict), "\"%s\"", nees_verdict(m));
  }
  char buf[2048];
  std::snprintf(
      buf, sizeof(buf),
      "{\"alignment\": \"%s\", \"poses_evaluated\": %d, \"poses_outside_groundtruth\": %d, "
      "\"ate_rmse_m\": %.6f, \"ate_max_m\": %.6f, \"orientation_rmse_deg\": %.4f, "
      "\"final_error_m\": %.6f, \"path_length_m\": %.4f, \"rpe_pairs\": %d, "
      "\"rpe_translation_per_m\": %.6f, \"rpe_rotation_deg_per_m\": %.5f, "
      "\"nees_count\": %d, \"nees_mean\": %s, \"nees_fraction_in_95\": %s, "
      "\"nees_not_positive_definite\": %d, \"nees_ratio\": %s, \"nees_ratio_low\": %s, "
      "\"nees_ratio_high\": %s, \"nees_effective_count\": %s, \"nees_verdict\": %s}",
      name_of(alignment), m.poses_evaluated, m.poses_outside_groundtruth, m.ate_rmse_m, m.ate_max_m,
      m.orientation_rmse_deg, m.final_error_m, m.path_length_m, m.rpe_pairs,
      m.rpe_translation_per_m, m.rpe_rotation_deg_per_m, m.nees_count,
      m.nees_count > 0 ? std::to_string(m.nees_mean).c_str() : "null",
      m.nees_count > 0 ? std::to_string(m.nees_fraction_in_95).c_str() : "null",
      m.nees_not_positive_definite,
      m.nees_count > 0 ? std::to_string(m.nees_ratio).c_str() : "null",
      m.nees_count > 0 ? std::to_string(m.nees_ratio_low).c_str() : "null",
      m.nees_count > 0 ? std::to_string(m.nees_ratio_high).c_str() : "null",
      m.nees_count > 0 ? std::to_string(m.nees_effective_count).c_str() : "null", verdict);
  return buf;
}

std::string to_text(const Metrics& m, Alignment alignment) {
  char buf[1024];
  int len = std::snprintf(buf, sizeof(buf),
                          "alignment             %s\n"
                          "poses evaluated       %d (%d outside the ground truth's time span)\n"
                          "path length           %.2f m\n"
                          "ATE RMSE              %.4f m (max %.4f m)\n"
                          "orientation RMSE      %.3f deg\n"
                          "final position error  %.4f m (%.2f %% of the path)\n"
                          "RPE per metre         %.4f m/m, %.3f deg/m (%d pairs)\n",
                          name_of(alignment), m.poses_evaluated, m.poses_outside_groundtruth,
                          m.path_length_m, m.ate_rmse_m, m.ate_max_m, m.orientation_rmse_deg,
                          m.final_error_m,
                          m.path_length_m > 0.0 ? 100.0 * m.final_error_m / m.path_length_m : 0.0,
                          m.rpe_translation_per_m, m.rpe_rotation_deg_per_m, m.rpe_pairs);
  std::string out(buf, static_cast<std::size_t>(std::max(0, len)));
  if (m.nees_count > 0) {
    std::snprintf(buf, sizeof(buf),
                  "position NEES         mean %.3f = %.2f x its consistent value 3 (95 %% band "
                  "%.2f-%.2f: %d poses, correlated, worth %.0f independent ones): %s; %.1f %% "
                  "of poses inside their own 95 %% bounds\n",
                  m.nees_mean, m.nees_ratio, m.nees_ratio_low, m.nees_ratio_high, m.nees_count,
                  m.nees_effective_count, nees_verdict(m), 100.0 * m.nees_fraction_in_95);
    out += buf;
    std::snprintf(buf, sizeof(buf),
                  "                      (NEES: each pose's squared position error weighed by the "
                  "inverse of the covariance the estimator claims; 3 on average when the claim "
                  "is honest, above: overconfident; tools/eval/README.md, \"Reading the "
                  "numbers\")\n");
  } else {
    std::snprintf(buf, sizeof(buf), "position NEES         no covariances\n");
  }
  out += buf;
  if (m.nees_not_positive_definite > 0) {
    std::snprintf(buf, sizeof(buf),
                  "                      not positive definite, left out: %d covariances (the "
                  "first at t = %.6f s)\n",
                  m.nees_not_positive_definite, m.first_not_positive_definite_s);
    out += buf;
  }
  return out;
}

}  // namespace cleanslam::evaluation
