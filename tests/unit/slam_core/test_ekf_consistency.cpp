#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Cholesky>

#include "cleanslam/slam_core/camera_frame_measurement.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/prediction_model.hpp"

// Feature-level Monte Carlo: a camera drives an arc in a room with point landmarks on the walls;
// odometry and pixel noise are drawn exactly as the filter assumes (eps_cal = 0), data
// association is known.
//
// Findings (50 runs; this test runs 20 steps, the variations below were measured with 30):
// - Landmarks entered at their true depth with 0.1 m along the ray: the average pose NEES is
//   6.01 on x86-64 and 5.85 on aarch64 (FMA changes the random paths), 20 steps, every step inside
//   its per-step band 5.08..7.00: prediction, update and initialization are consistent.
// - The paper's undelayed initialization (assumed depth 5 m, eps_ct 30 m; true depths 1-9 m): the
//   average pose NEES is 21.7 on x86-64, 26.0 on aarch64 (20 steps; 22 with 30 on x86-64), 3.6-4.3
//   times the 6 expected, mostly yaw (normalized yaw error 9.6), then pitch (3.5) and z (3.0). It
//   does not depend on eps_ct (3 m: 21, 100 m: 22) and stays near 20 without pixel noise, so it is
//   linearization error, not noise: the Jacobian of eq. 23 uses the estimated landmark vector
//   Delta_j, which is metres off along the ray while the depth is unknown, and the product of that
//   error with the orientation error (Assumption 1 of Section 2.5 is violated) exceeds eps_cn.
//   Inflating eps_cn as the paper's experiments did (eps_cn of 10 cm) restores it: eps_cal 0.5 px
//   gives 15, 1 px 9.9, 2 px 7.2. (These figures predate the depth bounds, now on by default:
//   with them the average is 24.2 on x86-64.)
// - The consider (Schmidt) update of young landmarks (EkfConfig::consider_young_landmarks) fixes
//   it: a landmark whose depth std. dev. relative to the camera exceeds young_depth_std_fraction
//   of its depth updates only itself. Average pose NEES on x86-64 by that fraction: 0.05: 5.95
//   (20/20 steps inside the band), 0.1: 7.5, 0.2: 13.6, 0.3: 17.4, 0.5: 19.1, off: 24.2.
namespace cs = cleanslam::slam_core;
namespace hal = cleanslam::hal;

namespace {

constexpr int kRuns = 50;
constexpr int kSteps = 20;
constexpr int kMaxInView = 10;

// Wilson-Hilferty approximation of the chi-square quantile with k dof at standard normal z.
double chi2_quantile(double k, double z) {
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3.0);
}

std::vector<Eigen::Vector3d> make_room(std::mt19937& rng) {
  std::uniform_real_distribution<double> along(-1.0, 1.0);
  std::uniform_real_distribution<double> height(-0.4, 1.6);
  std::vector<Eigen::Vector3d> lm;
  for (int i = 0; i < 25; ++i) {
    lm.emplace_back(5.0, 4.0 * along(rng), height(rng));
    lm.emplace_back(-5.0, 4.0 * along(rng), height(rng));
    lm.emplace_back(5.0 * along(rng), 4.0, height(rng));
    lm.emplace_back(5.0 * along(rng), -4.0, height(rng));
  }
  return lm;
}

struct RunResult {
  std::array<double, kSteps> nees{};
  int fused = 0;
};

// known_depth: enter landmarks at their true depth with 0.1 m along the ray instead of the
// assumed depth with eps_ct.
RunResult run_once(std::uint32_t seed, bool known_depth, double young_fraction) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const std::vector<Eigen::Vector3d> world = make_room(rng);

  hal::Calibration calibration;
  cs::EkfConfig config;
  config.eps_cal_px = 0.0;
  config.eps_trk_px = 0.5;
  config.max_landmarks = 24;
  config.consider_young_landmarks = young_fraction > 0.0;
  config.young_depth_std_fraction = young_fraction;
  auto ekf = std::make_unique<cs::Ekf>(calibration, config);

  cs::Vector6d q_sigma;
  q_sigma << 0.003, 0.001, 0.0005, 0.0005, 0.0005, 0.002;
  const cs::Matrix6d Q = q_sigma.cwiseProduct(q_sigma).asDiagonal();
  cs::Vector6d p0_sigma;
  p0_sigma << 0.01, 0.01, 0.002, 0.002, 0.002, 0.005;
  const cs::Matrix6d P0 = p0_sigma.cwiseProduct(p0_sigma).asDiagonal();

  cs::Vector6d truth;
  truth << -2.0, -1.0, 0.0, 0.0, 0.0, 0.0;
  cs::Vector6d start = truth;
  for (int i = 0; i < 6; ++i) {
    start(i) += p0_sigma(i) * gauss(rng);
  }
  EXPECT_TRUE(ekf->reset(start, P0));

  std::vector<int> slot_of(world.size(), -1);
  std::array<int, hal::kMaxLandmarks> owner{};
  owner.fill(-1);
  RunResult result;
  for (int k = 0; k < kSteps; ++k) {
    if (k > 0) {
      const Eigen::Vector3d dx(0.15, 0.0, 0.0);
      const Eigen::Vector3d dpsi(0.0, 0.0, 0.08);
      truth = cs::predict_pose(truth, dx, dpsi);
      cs::OdometryIncrement u;
      for (int i = 0; i < 3; ++i) {
        u.dx_c(i) = dx(i) + q_sigma(i) * gauss(rng);
        u.dpsi_c(i) = dpsi(i) + q_sigma(3 + i) * gauss(rng);
      }
      u.Q = Q;
      EXPECT_TRUE(ekf->predict(u).applied());
    }
    // What the camera sees, with pixel noise.
    std::array<cs::Observation, hal::kMaxObservationsPerFrame> obs{};
    int m = 0;
    std::vector<std::pair<int, Eigen::Vector2d>> fresh;
    for (std::size_t j = 0; j < world.size(); ++j) {
      const Eigen::Vector3d pc = cs::predict_camera_point(truth, world[j]);
      Eigen::Vector2d px;
      if (pc.x() < 0.5 || !ekf->camera().project(pc, px, nullptr)) {
        continue;
      }
      px += config.eps_trk_px * Eigen::Vector2d(gauss(rng), gauss(rng));
      if (!ekf->camera().in_image(px.x(), px.y())) {
        continue;
      }
      const int slot = slot_of[j];
      if (slot >= 0 && ekf->slot_used(slot) &&
          owner[static_cast<std::size_t>(slot)] == static_cast<int>(j)) {
        if (m < kMaxInView) {
          obs[static_cast<std::size_t>(m++)] = {slot, px.x(), px.y()};
        }
      } else {
        fresh.emplace_back(static_cast<int>(j), px);
      }
    }
    if (m > 0) {
      result.fused += ekf->update(obs.data(), m).fused;
    }
    int in_view = m;
    for (const auto& [j, px] : fresh) {
      if (in_view >= kMaxInView) {
        break;
      }
      const double depth =
          cs::predict_camera_point(truth, world[static_cast<std::size_t>(j)]).norm();
      const int slot = known_depth ? ekf->initialize_landmark(px.x(), px.y(), depth, 0.1)
                                   : ekf->initialize_landmark(px.x(), px.y());
      if (slot >= 0) {
        slot_of[static_cast<std::size_t>(j)] = slot;
        owner[static_cast<std::size_t>(slot)] = j;
        ++in_view;
      }
    }
    cs::Vector6d e = truth - ekf->camera_pose();
    for (int i = 3; i < 6; ++i) {
      e(i) = cs::wrap_angle(e(i));
    }
    const cs::Matrix6d P = ekf->pose_covariance();
    result.nees[static_cast<std::size_t>(k)] = e.dot(P.ldlt().solve(e));
  }
  return result;
}

struct NeesSummary {
  double overall = 0.0;
  int inside = 0;
  long fused = 0;
};

NeesSummary monte_carlo(bool known_depth, double young_fraction) {
  std::array<double, kSteps> mean{};
  NeesSummary out;
  for (int r = 0; r < kRuns; ++r) {
    const RunResult res =
        run_once(1000U + static_cast<std::uint32_t>(r), known_depth, young_fraction);
    for (int k = 0; k < kSteps; ++k) {
      mean[static_cast<std::size_t>(k)] += res.nees[static_cast<std::size_t>(k)] / kRuns;
    }
    out.fused += res.fused;
  }
  // Per step: the average of kRuns NEES values (6 dof each) is chi2(6 kRuns) / kRuns.
  const double lo = chi2_quantile(6.0 * kRuns, -1.959964) / kRuns;
  const double hi = chi2_quantile(6.0 * kRuns, 1.959964) / kRuns;
  for (int k = 0; k < kSteps; ++k) {
    const double v = mean[static_cast<std::size_t>(k)];
    out.inside += (v >= lo && v <= hi) ? 1 : 0;
    out.overall += v / kSteps;
  }
  std::printf(
      "%s, consider below %.2f: per-step band [%.2f, %.2f], steps inside %d/%d, average pose "
      "NEES %.3f, observations fused %ld\n",
      known_depth ? "known depth" : "undelayed init", young_fraction, lo, hi, out.inside, kSteps,
      out.overall, out.fused);
  return out;
}

}  // namespace

TEST(EkfConsistency, PoseNeesInsideChiSquareBandWithLandmarkDepthsKnown) {
  const NeesSummary s = monte_carlo(true, 0.0);
  // The steps of one run are correlated, so the time average is held to the per-step band of
  // kRuns independent runs, chi2(6 kRuns) / kRuns, not to a band of kRuns * kSteps samples.
  EXPECT_GT(s.fused, kRuns * kSteps * 5);
  EXPECT_GE(s.inside, kSteps * 8 / 10);
  EXPECT_GT(s.overall, chi2_quantile(6.0 * kRuns, -1.959964) / kRuns);
  EXPECT_LT(s.overall, chi2_quantile(6.0 * kRuns, 1.959964) / kRuns);
}

TEST(EkfConsistency, PoseNeesOfUndelayedInitializationInsideBandWithConsiderUpdate) {
  // Young landmarks (relative depth std. dev. above 5 %) update only themselves: the pose never
  // sees the linearization error of their unknown depth.
  const NeesSummary s = monte_carlo(false, 0.05);
  EXPECT_GT(s.fused, kRuns * kSteps * 5);
  EXPECT_GE(s.inside, kSteps * 8 / 10);
  EXPECT_GT(s.overall, chi2_quantile(6.0 * kRuns, -1.959964) / kRuns);
  EXPECT_LT(s.overall, chi2_quantile(6.0 * kRuns, 1.959964) / kRuns);
}

TEST(EkfConsistency, PoseNeesOfUndelayedInitializationIsKnownOverconfident) {
  // Not inside the band (see the top of this file): this guards the measured figure, so that a
  // change that makes it worse (or, welcome, better) is noticed.
  const NeesSummary s = monte_carlo(false, 0.0);
  EXPECT_GT(s.fused, kRuns * kSteps * 5);
  EXPECT_GT(s.overall, 6.0);
  EXPECT_LT(s.overall, 30.0);
}
