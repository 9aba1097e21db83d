#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "cleanslam/evaluation/evaluation.hpp"
#include "cleanslam/sim_hal/sim/random.hpp"

namespace fs = std::filesystem;
using namespace cleanslam;
namespace ev = cleanslam::evaluation;

namespace {

std::array<double, 4> yaw_quat(double yaw) {
  return {std::cos(0.5 * yaw), 0.0, 0.0, std::sin(0.5 * yaw)};
}

// A planar ground truth: a 4 m x 2 m loop-like path sampled at 100 Hz for 60 s.
std::vector<readers::GroundTruthPose> make_gt() {
  std::vector<readers::GroundTruthPose> gt;
  for (int k = 0; k <= 6000; ++k) {
    const double t = 0.01 * k;
    const double a = 2.0 * std::numbers::pi * t / 60.0;
    readers::GroundTruthPose p;
    p.t_ns = 1'000'000'000 + static_cast<hal::TimeNs>(k) * 10'000'000;
    p.position_m = {2.0 * std::sin(a), 1.0 - std::cos(a), 0.0};
    p.orientation_wxyz = yaw_quat(std::atan2(std::sin(a), 2.0 * std::cos(a)));
    gt.push_back(p);
  }
  return gt;
}

// The ground truth at 10 Hz (interpolated mid-sample stamps), moved by a rigid transform
// (yaw `yaw`, translation t) and with position noise.
std::vector<ev::TumPose> make_estimate(const std::vector<readers::GroundTruthPose>& gt, double yaw,
                                       std::array<double, 3> t, double noise, double z_tilt = 0.0) {
  std::vector<ev::TumPose> est;
  sim_hal::sim::Random rng(5);
  const double c = std::cos(yaw), s = std::sin(yaw);
  for (hal::TimeNs tn = gt.front().t_ns + 5'000'000; tn < gt.back().t_ns; tn += 100'000'000) {
    const auto g = ev::interpolate(gt, tn);
    EXPECT_TRUE(g.has_value());
    ev::TumPose p = *g;
    const double x = g->position[0], y = g->position[1];
    p.position = {c * x - s * y + t[0] + rng.gaussian(noise),
                  s * x + c * y + t[1] + rng.gaussian(noise),
                  t[2] + z_tilt * x + rng.gaussian(noise)};
    const double gyaw = 2.0 * std::atan2(g->orientation_wxyz[3], g->orientation_wxyz[0]);
    p.orientation_wxyz = yaw_quat(gyaw + yaw);
    est.push_back(p);
  }
  return est;
}

}  // namespace

TEST(Evaluation, InterpolatesGroundTruth) {
  std::vector<readers::GroundTruthPose> gt(2);
  gt[0].t_ns = 0;
  gt[0].position_m = {0, 0, 0};
  gt[0].orientation_wxyz = yaw_quat(0.0);
  gt[1].t_ns = 100;
  gt[1].position_m = {1, 2, 0};
  gt[1].orientation_wxyz = yaw_quat(1.0);
  const auto p = ev::interpolate(gt, 25);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->position[0], 0.25, 1e-12);
  EXPECT_NEAR(p->position[1], 0.5, 1e-12);
  EXPECT_NEAR(2.0 * std::atan2(p->orientation_wxyz[3], p->orientation_wxyz[0]), 0.25, 1e-12);
  EXPECT_FALSE(ev::interpolate(gt, -1).has_value());
  EXPECT_FALSE(ev::interpolate(gt, 101).has_value());
  EXPECT_TRUE(ev::interpolate(gt, 100).has_value());
}

TEST(Evaluation, PerfectEstimateHasZeroErrors) {
  const auto gt = make_gt();
  const auto est = make_estimate(gt, 0.0, {0, 0, 0}, 0.0);
  for (auto a : {ev::Alignment::kNone, ev::Alignment::kSe2, ev::Alignment::kSe3}) {
    auto m = ev::evaluate(gt, est, a);
    ASSERT_TRUE(m.ok()) << m.error();
    EXPECT_NEAR(m->ate_rmse_m, 0.0, 1e-9);
    EXPECT_NEAR(m->final_error_m, 0.0, 1e-9);
    EXPECT_NEAR(m->rpe_translation_per_m, 0.0, 1e-9);
    EXPECT_GT(m->rpe_pairs, 100);
    EXPECT_NEAR(m->path_length_m, 2.0 * std::numbers::pi * 1.5, 0.5);  // about the ellipse
  }
}

TEST(Evaluation, RigidOffsetIsRemovedByAlignmentButNotByNone) {
  const auto gt = make_gt();
  // A start-pose offset: the estimate is a rigidly moved copy, so relative-to-first-pose and
  // rigid alignment both remove it; RPE never sees it.
  const auto est = make_estimate(gt, 0.7, {3.0, -1.0, 0.0}, 0.0);
  for (auto a : {ev::Alignment::kNone, ev::Alignment::kSe2, ev::Alignment::kSe3}) {
    auto m = ev::evaluate(gt, est, a);
    ASSERT_TRUE(m.ok());
    EXPECT_NEAR(m->ate_rmse_m, 0.0, 1e-6);
    EXPECT_NEAR(m->rpe_translation_per_m, 0.0, 1e-9);
  }
  auto se2 = ev::evaluate(gt, est, ev::Alignment::kSe2);
  EXPECT_NEAR(std::atan2(se2->rotation[3], se2->rotation[0]), -0.7, 1e-9);
}

TEST(Evaluation, NoneKeepsDriftThatAlignmentSpreads) {
  auto gt = make_gt();
  auto est = make_estimate(gt, 0.0, {0, 0, 0}, 0.0);
  // A position error that grows with time: drift.
  for (std::size_t i = 0; i < est.size(); ++i) {
    const double d = 0.002 * static_cast<double>(i);
    est[i].position[0] += d;
  }
  auto none = ev::evaluate(gt, est, ev::Alignment::kNone);
  auto se2 = ev::evaluate(gt, est, ev::Alignment::kSe2);
  ASSERT_TRUE(none.ok() && se2.ok());
  const double final_drift = 0.002 * static_cast<double>(est.size() - 1);
  EXPECT_NEAR(none->final_error_m, final_drift, 1e-6);
  EXPECT_LT(se2->ate_rmse_m, none->ate_rmse_m);
  EXPECT_GT(none->rpe_translation_per_m, 0.0);
}

TEST(Evaluation, Se3RemovesTiltThatSe2Cannot) {
  auto gt = make_gt();
  // A 3-D rotation about x of the whole estimate (positions only matter for ATE).
  auto est = make_estimate(gt, 0.0, {0, 0, 0}, 0.0);
  const double a = 0.2, c = std::cos(a), s = std::sin(a);
  for (auto& p : est) {
    const double y = p.position[1], z = p.position[2];
    p.position[1] = c * y - s * z;
    p.position[2] = s * y + c * z;
  }
  auto se2 = ev::evaluate(gt, est, ev::Alignment::kSe2);
  auto se3 = ev::evaluate(gt, est, ev::Alignment::kSe3);
  ASSERT_TRUE(se2.ok() && se3.ok());
  EXPECT_NEAR(se3->ate_rmse_m, 0.0, 1e-9);
  EXPECT_GT(se2->ate_rmse_m, 0.05);
}

TEST(Evaluation, NoiseGivesMatchingAteAndConsistentNees) {
  const auto gt = make_gt();
  const double sigma = 0.05;
  auto est = make_estimate(gt, 0.0, {0, 0, 0}, sigma);
  for (auto& p : est) {
    p.position_covariance =
        std::array<double, 9>{sigma * sigma, 0, 0, 0, sigma * sigma, 0, 0, 0, sigma * sigma};
  }
  auto m = ev::evaluate(gt, est, ev::Alignment::kSe3);
  ASSERT_TRUE(m.ok());
  EXPECT_NEAR(m->ate_rmse_m, sigma * std::sqrt(3.0), 0.01);
  EXPECT_EQ(m->nees_count, m->poses_evaluated);
  EXPECT_NEAR(m->nees_mean, 3.0, 0.4);
  EXPECT_NEAR(m->nees_fraction_in_95, 0.95, 0.04);
  // An over-confident covariance gives a large NEES.
  for (auto& p : est) {
    p.position_covariance = std::array<double, 9>{
        1e-4 * sigma * sigma, 0, 0, 0, 1e-4 * sigma * sigma, 0, 0, 0, 1e-4 * sigma * sigma};
  }
  auto bad = ev::evaluate(gt, est, ev::Alignment::kSe3);
  EXPECT_GT(bad->nees_mean, 1000.0);
  EXPECT_EQ(bad->nees_not_positive_definite, 0);
}

// The mean NEES is stated as a ratio to 3 with the 95 % band of the mean of N chi-square(3)
// values: consistent noise lands inside, a covariance 4x too small (ratio 4) above it, one 4x
// too large below it.
TEST(Evaluation, NeesRatioWithItsBandAndVerdict) {
  const auto gt = make_gt();
  const double sigma = 0.05;
  auto est = make_estimate(gt, 0.0, {0, 0, 0}, sigma);
  const auto with_variance = [&](double v) {
    for (auto& p : est) {
      p.position_covariance = std::array<double, 9>{v, 0, 0, 0, v, 0, 0, 0, v};
    }
    return ev::evaluate(gt, est, ev::Alignment::kSe3);
  };
  auto m = with_variance(sigma * sigma);
  ASSERT_TRUE(m.ok());
  EXPECT_NEAR(m->nees_ratio, m->nees_mean / 3.0, 1e-12);
  // Independent errors: the effective count is about the pose count.
  EXPECT_GT(m->nees_effective_count, 0.5 * m->nees_count);
  const double n = m->nees_effective_count;
  // chi-square(3N)/(3N): mean 1, standard deviation sqrt(2/(3N)).
  EXPECT_NEAR(m->nees_ratio_low, 1.0 - 1.96 * std::sqrt(2.0 / (3.0 * n)), 0.01);
  EXPECT_NEAR(m->nees_ratio_high, 1.0 + 1.96 * std::sqrt(2.0 / (3.0 * n)), 0.01);
  EXPECT_STREQ(ev::nees_verdict(*m), "consistent") << m->nees_ratio;
  const std::string text = ev::to_text(*m, ev::Alignment::kSe3);
  EXPECT_NE(text.find(": consistent;"), std::string::npos);
  // Where the NEES is printed, one line says what it is and where the longer text is.
  EXPECT_NE(text.find("(NEES: each pose's squared position error weighed by the inverse of the "
                      "covariance the estimator claims; 3 on average when the claim is honest"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("tools/eval/README.md, \"Reading the numbers\""), std::string::npos) << text;
  auto over = with_variance(sigma * sigma / 4.0);
  EXPECT_NEAR(over->nees_ratio, 4.0 * m->nees_ratio, 1e-9);
  EXPECT_STREQ(ev::nees_verdict(*over), "overconfident");
  EXPECT_NE(ev::to_json(*over, ev::Alignment::kSe3).find("\"nees_verdict\": \"overconfident\""),
            std::string::npos);
  auto under = with_variance(sigma * sigma * 4.0);
  EXPECT_STREQ(ev::nees_verdict(*under), "conservative");
  est.clear();
  est = make_estimate(gt, 0.0, {0, 0, 0}, sigma);
  auto none = ev::evaluate(gt, est, ev::Alignment::kSe3);
  EXPECT_STREQ(ev::nees_verdict(*none), "");
  EXPECT_NE(ev::to_json(*none, ev::Alignment::kSe3).find("\"nees_verdict\": null"),
            std::string::npos);
}

// An error that persists over the poses (a slowly wandering offset, first-order autoregressive
// with a correlation of 0.98 from pose to pose) is worth far fewer independent poses than it has:
// the band widens accordingly, where counting every pose would call a consistent run
// overconfident or conservative on chance alone.
TEST(Evaluation, NeesBandCountsCorrelatedPosesAsFewer) {
  const auto gt = make_gt();
  auto est = make_estimate(gt, 0.0, {0, 0, 0}, 0.0);
  const double sigma = 0.05;
  const double rho = 0.98;
  sim_hal::sim::Random rng(11);
  std::array<double, 3> e{rng.gaussian(sigma), rng.gaussian(sigma), rng.gaussian(sigma)};
  for (std::size_t i = 0; i < est.size(); ++i) {
    for (std::size_t a = 0; a < 3; ++a) {
      e[a] = rho * e[a] + std::sqrt(1.0 - rho * rho) * rng.gaussian(sigma);
      est[i].position[a] += e[a];
    }
    est[i].position_covariance =
        std::array<double, 9>{sigma * sigma, 0, 0, 0, sigma * sigma, 0, 0, 0, sigma * sigma};
  }
  auto m = ev::evaluate(gt, est, ev::Alignment::kNone);
  ASSERT_TRUE(m.ok()) << m.error();
  ASSERT_GT(m->nees_count, 100);
  EXPECT_LT(m->nees_effective_count, 0.2 * m->nees_count);
  const double independent_high = 1.0 + 1.96 * std::sqrt(2.0 / (3.0 * m->nees_count));
  EXPECT_GT(m->nees_ratio_high, independent_high + 0.05);
}

// A covariance that is not positive definite is left out of the NEES, and said so: before, the
// pose count was the only trace of it.
TEST(Evaluation, CovariancesNotPositiveDefiniteAreCountedNotHidden) {
  const auto gt = make_gt();
  auto est = make_estimate(gt, 0.0, {0, 0, 0}, 0.05);
  for (auto& p : est) {
    p.position_covariance = std::array<double, 9>{0.0025, 0, 0, 0, 0.0025, 0, 0, 0, 0.0025};
  }
  est[5].position_covariance = std::array<double, 9>{-5.0, 0, 0, 0, 0.0025, 0, 0, 0, 0.0025};
  est[9].position_covariance = std::array<double, 9>{};
  auto m = ev::evaluate(gt, est, ev::Alignment::kNone);
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m->nees_count, m->poses_evaluated - 2);
  EXPECT_EQ(m->nees_not_positive_definite, 2);
  EXPECT_DOUBLE_EQ(m->first_not_positive_definite_s, hal::to_seconds(est[5].t_ns));
  const std::string text = ev::to_text(*m, ev::Alignment::kNone);
  EXPECT_NE(text.find("not positive definite, left out: 2 covariances"), std::string::npos) << text;
  EXPECT_NE(ev::to_json(*m, ev::Alignment::kNone).find("\"nees_not_positive_definite\": 2"),
            std::string::npos);
}

TEST(Evaluation, EstimatesOutsideTheGroundTruthAreCounted) {
  const auto gt = make_gt();
  auto est = make_estimate(gt, 0.0, {0, 0, 0}, 0.0);
  ev::TumPose late = est.back();
  late.t_ns = gt.back().t_ns + 1'000'000'000;
  est.push_back(late);
  auto m = ev::evaluate(gt, est, ev::Alignment::kNone);
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m->poses_outside_groundtruth, 1);
  std::vector<ev::TumPose> none_inside{late};
  EXPECT_FALSE(ev::evaluate(gt, none_inside, ev::Alignment::kNone).ok());
}

TEST(Evaluation, ReadsTumAndCovarianceFiles) {
  const fs::path dir =
      fs::temp_directory_path() / ("cleanslam_eval_tum_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string tum = (dir / "t.tum").string();
  std::ofstream(tum)
      << "# t x y z qx qy qz qw\n1.0 0 0 0 0 0 0 1\n1.5 1 2 3 0 0 0.7071068 0.7071068\n";
  std::ofstream(tum + ".cov") << "1.0 1 0 0 0 1 0 0 0 1\n"
                              << "1.5";
  std::ofstream(tum + ".cov", std::ios::app) << [] {
    std::string s;
    for (int i = 0; i < 36; ++i) {
      s += (i % 7 == 0) ? " 2" : " 0";
    }
    return s + "\n";
  }();
  auto est = ev::read_tum(tum);
  ASSERT_TRUE(est.ok()) << est.error();
  ASSERT_EQ(est->size(), 2U);
  EXPECT_EQ((*est)[1].t_ns, 1'500'000'000);
  EXPECT_NEAR((*est)[1].orientation_wxyz[0], std::sqrt(0.5), 1e-6);
  EXPECT_NEAR((*est)[1].position[2], 3.0, 1e-12);
  auto s = ev::read_covariances(tum + ".cov", *est);
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_TRUE((*est)[1].position_covariance.has_value());
  EXPECT_DOUBLE_EQ((*est)[1].position_covariance->at(4), 2.0);
  EXPECT_DOUBLE_EQ((*est)[0].position_covariance->at(0), 1.0);
  std::ofstream(tum) << "1.0 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n";
  auto bad = ev::read_tum(tum);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("t.tum:2: t: time stamps must increase"), std::string::npos)
      << bad.error();
  std::ofstream(tum) << "1.0 0 0 x 0 0 0 1\n";
  bad = ev::read_tum(tum);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("t.tum:1: field 4: expected a finite number, got \"x\""),
            std::string::npos)
      << bad.error();
  fs::remove_all(dir);
}
