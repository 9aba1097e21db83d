#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "cleanslam/slam_core/frontend/chi_square.hpp"
#include "cleanslam/slam_core/frontend/harris.hpp"
#include "cleanslam/slam_core/frontend/jcbb.hpp"
#include "cleanslam/slam_core/frontend/patch.hpp"
#include "cleanslam/slam_core/frontend/search_region.hpp"
#include "cleanslam/slam_core/frontend/tracker.hpp"
#include "frontend_synthetic.hpp"

namespace fe = cleanslam::slam_core::frontend;
using cleanslam::test::GrayImage;
using cleanslam::test::render;
using cleanslam::test::Warp;

namespace {

// Innovation covariance of m pixels sharing one pose error (sigma_common per axis, fully
// correlated between landmarks) plus independent pixel noise sigma_pixel.
Eigen::MatrixXd common_shift_covariance(int m, double sigma_common, double sigma_pixel) {
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(2 * m, 2 * m);
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) {
      S(2 * i, 2 * j) = sigma_common * sigma_common;
      S(2 * i + 1, 2 * j + 1) = sigma_common * sigma_common;
    }
    S(2 * i, 2 * i) += sigma_pixel * sigma_pixel;
    S(2 * i + 1, 2 * i + 1) += sigma_pixel * sigma_pixel;
  }
  return S;
}

double subset_nis(const Eigen::VectorXd& nu, const Eigen::MatrixXd& S,
                  const std::vector<int>& idx) {
  const auto k = static_cast<Eigen::Index>(idx.size());
  Eigen::VectorXd n(2 * k);
  Eigen::MatrixXd s(2 * k, 2 * k);
  for (Eigen::Index a = 0; a < k; ++a) {
    n.segment<2>(2 * a) = nu.segment<2>(2 * idx[static_cast<std::size_t>(a)]);
    for (Eigen::Index b = 0; b < k; ++b) {
      s.block<2, 2>(2 * a, 2 * b) =
          S.block<2, 2>(2 * idx[static_cast<std::size_t>(a)], 2 * idx[static_cast<std::size_t>(b)]);
    }
  }
  return n.dot(s.llt().solve(n));
}

}  // namespace

TEST(FrontendChiSquare, MatchesTabulatedQuantiles) {
  EXPECT_NEAR(fe::chi2_quantile_even(2, 0.99), 9.2103, 1e-4);
  EXPECT_NEAR(fe::chi2_quantile_even(2, 0.95), 5.9915, 1e-4);
  EXPECT_NEAR(fe::chi2_quantile_even(4, 0.95), 9.4877, 1e-4);
  EXPECT_NEAR(fe::chi2_quantile_even(10, 0.99), 23.2093, 1e-4);
  EXPECT_NEAR(fe::chi2_quantile_even(32, 0.99), 53.4858, 1e-3);
  EXPECT_EQ(fe::chi2_quantile_even(3, 0.99), 0.0);
  EXPECT_EQ(fe::chi2_quantile_even(0, 0.99), 0.0);
}

TEST(FrontendJcbb, AllConsistentObservationsAreInliers) {
  const int m = 6;
  const Eigen::MatrixXd S = common_shift_covariance(m, 5.0, 1.0);
  Eigen::VectorXd nu(2 * m);
  for (int i = 0; i < m; ++i) {
    nu(2 * i) = 4.0 + 0.3 * (i % 3 - 1);
    nu(2 * i + 1) = -3.0 + 0.2 * (i % 2);
  }
  fe::Jcbb jcbb;
  bool inlier[fe::Jcbb::kMaxObservations];
  const fe::JcbbResult r = jcbb.solve(nu.data(), S.data(), m, inlier);
  EXPECT_EQ(r.inlier_count, m);
  EXPECT_TRUE(r.update);
  EXPECT_NEAR(r.joint_nis, subset_nis(nu, S, {0, 1, 2, 3, 4, 5}), 1e-9);
  for (int i = 0; i < m; ++i) {
    EXPECT_TRUE(inlier[i]);
  }
}

TEST(FrontendJcbb, RemovesAnIndividuallyCompatibleButJointlyInconsistentMatch) {
  const int m = 5;
  const Eigen::MatrixXd S = common_shift_covariance(m, 8.0, 1.0);
  Eigen::VectorXd nu(2 * m);
  for (int i = 0; i < m; ++i) {
    nu(2 * i) = 10.0;
    nu(2 * i + 1) = 2.0;
  }
  nu(2 * 3) = -8.0;  // one period of a repeated pattern away
  // Individually compatible: 18^2 / 65 < 9.21.
  EXPECT_LT(nu(6) * nu(6) / S(6, 6), 9.21);
  fe::Jcbb jcbb;
  bool inlier[fe::Jcbb::kMaxObservations];
  const fe::JcbbResult r = jcbb.solve(nu.data(), S.data(), m, inlier);
  EXPECT_EQ(r.inlier_count, 4);
  EXPECT_EQ(r.rejected_individually, 0);
  EXPECT_FALSE(inlier[3]);
  EXPECT_TRUE(inlier[0] && inlier[1] && inlier[2] && inlier[4]);
}

TEST(FrontendJcbb, FewerThanMinInliersMeansNoUpdate) {
  const int m = 2;
  const Eigen::MatrixXd S = common_shift_covariance(m, 3.0, 1.0);
  const Eigen::VectorXd nu = Eigen::VectorXd::Constant(2 * m, 1.0);
  fe::Jcbb jcbb;
  bool inlier[fe::Jcbb::kMaxObservations];
  const fe::JcbbResult r = jcbb.solve(nu.data(), S.data(), m, inlier);
  EXPECT_EQ(r.inlier_count, 2);
  EXPECT_FALSE(r.update);
  fe::JcbbConfig two;
  two.min_inliers = 2;
  fe::Jcbb lenient(two);
  EXPECT_TRUE(lenient.solve(nu.data(), S.data(), m, inlier).update);
}

TEST(FrontendJcbb, RejectsNonFiniteAndOutOfRangeInput) {
  const int m = 4;
  Eigen::MatrixXd S = common_shift_covariance(m, 3.0, 1.0);
  Eigen::VectorXd nu = Eigen::VectorXd::Constant(2 * m, 0.5);
  nu(5) = std::numeric_limits<double>::quiet_NaN();
  fe::Jcbb jcbb;
  bool inlier[fe::Jcbb::kMaxObservations];
  fe::JcbbResult r = jcbb.solve(nu.data(), S.data(), m, inlier);
  EXPECT_EQ(r.inlier_count, 3);
  EXPECT_EQ(r.rejected_individually, 1);
  EXPECT_FALSE(inlier[2]);
  nu(5) = 0.5;
  S(0, 6) = std::numeric_limits<double>::infinity();
  r = jcbb.solve(nu.data(), S.data(), m, inlier);
  EXPECT_EQ(r.rejected_individually, 1);
  EXPECT_FALSE(inlier[0]);
  EXPECT_EQ(jcbb.solve(nu.data(), S.data(), fe::Jcbb::kMaxObservations + 1, inlier).inlier_count,
            0);
  EXPECT_EQ(jcbb.solve(nu.data(), S.data(), 0, inlier).inlier_count, 0);
}

TEST(FrontendJcbb, MatchesExhaustiveSearchOnRandomProblems) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  fe::Jcbb jcbb;
  for (int trial = 0; trial < 200; ++trial) {
    const int m = 1 + trial % 8;
    Eigen::MatrixXd A(2 * m, 2 * m);
    for (Eigen::Index i = 0; i < A.size(); ++i) {
      A.data()[i] = n01(rng);
    }
    const Eigen::MatrixXd S = 0.5 * A * A.transpose() + Eigen::MatrixXd::Identity(2 * m, 2 * m);
    const Eigen::MatrixXd L = S.llt().matrixL();
    Eigen::VectorXd z(2 * m);
    for (Eigen::Index i = 0; i < z.size(); ++i) {
      z(i) = n01(rng);
    }
    Eigen::VectorXd nu = L * z;
    for (int i = 0; i < m; ++i) {
      if (u01(rng) < 0.3) {
        nu(2 * i) += 6.0 * n01(rng);
        nu(2 * i + 1) += 6.0 * n01(rng);
      }
    }
    int best = 0;
    double best_nis = 0.0;
    for (int mask = 1; mask < (1 << m); ++mask) {
      std::vector<int> idx;
      bool individually = true;
      for (int i = 0; i < m; ++i) {
        if ((mask >> i) & 1) {
          idx.push_back(i);
          individually = individually && subset_nis(nu, S, {i}) <= jcbb.joint_bound(1);
        }
      }
      const auto k = static_cast<int>(idx.size());
      if (!individually || k < best) {
        continue;
      }
      const double nis = subset_nis(nu, S, idx);
      if (nis <= jcbb.joint_bound(k) && (k > best || nis < best_nis)) {
        best = k;
        best_nis = nis;
      }
    }
    bool inlier[fe::Jcbb::kMaxObservations];
    const fe::JcbbResult r = jcbb.solve(nu.data(), S.data(), m, inlier);
    ASSERT_EQ(r.inlier_count, best) << "trial " << trial;
    if (best > 0) {
      EXPECT_NEAR(r.joint_nis, best_nis, 1e-7 * (1.0 + best_nis)) << "trial " << trial;
      std::vector<int> idx;
      for (int i = 0; i < m; ++i) {
        if (inlier[i]) {
          idx.push_back(i);
        }
      }
      EXPECT_NEAR(subset_nis(nu, S, idx), r.joint_nis, 1e-7 * (1.0 + best_nis));
    }
  }
}

TEST(FrontendJcbb, HandlesTheFullCapacityQuickly) {
  const int m = fe::Jcbb::kMaxObservations;
  const Eigen::MatrixXd S = common_shift_covariance(m, 6.0, 1.0);
  Eigen::VectorXd nu(2 * m);
  for (int i = 0; i < m; ++i) {
    nu(2 * i) = 5.0 + ((i % 4 == 0) ? 14.0 : 0.1 * i);
    nu(2 * i + 1) = 1.0;
  }
  fe::Jcbb jcbb;
  bool inlier[fe::Jcbb::kMaxObservations];
  const fe::JcbbResult r = jcbb.solve(nu.data(), S.data(), m, inlier);
  EXPECT_EQ(r.inlier_count, 12);
  for (int i = 0; i < m; ++i) {
    EXPECT_EQ(inlier[i], i % 4 != 0) << i;
  }
  EXPECT_LT(r.nodes, 20000);
}

// A repeated pattern: one landmark sits on a texture that repeats every 20 px; a common pose error
// in the prediction puts a copy of it nearer than the landmark itself, so the tracker (rightly,
// by its own rule) picks the copy. Only the joint test sees that this one innovation disagrees
// with the others, which share the pose error.
TEST(FrontendJcbb, RepeatedPatternWrongMatchIsRemoved) {
  cleanslam::test::TextureOptions tex;
  tex.period_x = 20.0;
  tex.periodic_x0 = 140.0;
  tex.periodic_x1 = 220.0;
  const GrayImage ref = render(Warp{}, 320, 240, 1.0, 0.0, tex);
  Warp motion;
  motion.shift_x = 4.0;
  motion.shift_y = 2.0;
  const GrayImage cur = render(motion, 320, 240, 1.0, 0.0, tex);

  fe::HarrisDetector det;
  det.detect(ref.view(), 320, 240);
  std::vector<fe::Corner> lms;
  int periodic = -1;
  for (int i = 0; i < det.corner_count(); ++i) {
    const fe::Corner& c = det.corners()[i];
    if (c.y < 40 || c.y > 200) {
      continue;
    }
    if (periodic < 0 && c.x > 170 && c.x < 188) {
      periodic = static_cast<int>(lms.size());
      lms.push_back(c);
    } else if ((c.x > 40 && c.x < 120) || (c.x > 240 && c.x < 290)) {
      if (lms.size() < 7) {
        lms.push_back(c);
      }
    }
  }
  ASSERT_GE(periodic, 0);
  ASSERT_GE(lms.size(), 6U);
  const int m = static_cast<int>(lms.size());

  det.detect(cur.view(), 320, 240);
  fe::TrackerConfig tcfg;
  tcfg.max_corner_starts = 8;
  // The tracker's own refusal of look-alikes off: this is about JCBB removing what gets through.
  tcfg.ambiguity_ncc = -2.0F;
  const fe::Tracker tracker(tcfg);
  const double sigma_common = 8.0;
  const double sigma_pixel = 1.0;
  const Eigen::Vector2d pose_error(-12.0, 0.0);
  Eigen::VectorXd nu(2 * m);
  int tracked = 0;
  for (int i = 0; i < m; ++i) {
    fe::LandmarkPatch patch;
    ASSERT_TRUE(fe::capture_patch(ref.view(), lms[static_cast<std::size_t>(i)].x,
                                  lms[static_cast<std::size_t>(i)].y, 2.0, patch));
    fe::PatchTemplate tmpl;
    ASSERT_TRUE(fe::make_template(patch, 1.0, 3.0F, tmpl));
    const Eigen::Vector2d truth(lms[static_cast<std::size_t>(i)].x + 4.0,
                                lms[static_cast<std::size_t>(i)].y + 2.0);
    fe::PixelPrediction pred;
    pred.uv = truth + pose_error;
    pred.S =
        Eigen::Matrix2d::Identity() * (sigma_common * sigma_common + sigma_pixel * sigma_pixel);
    pred.depth_m = 2.0;
    pred.in_front = true;
    const fe::SearchRegion region = fe::make_search_region(pred, 320, 240);
    const fe::TrackResult r =
        tracker.track(cur.view(), tmpl, region, det.corners(), det.corner_count());
    ASSERT_TRUE(r.found) << "landmark " << i;
    ++tracked;
    const Eigen::Vector2d z(r.u_px, r.v_px);
    if (i == periodic) {
      EXPECT_NEAR((z - truth).norm(), 20.0, 0.3) << "the premise: the copy is matched";
    } else {
      EXPECT_LT((z - truth).norm(), 0.2) << "landmark " << i;
    }
    nu.segment<2>(2 * i) = z - pred.uv;
  }
  const Eigen::MatrixXd S = common_shift_covariance(m, sigma_common, sigma_pixel);
  fe::Jcbb jcbb;
  bool inlier[fe::Jcbb::kMaxObservations];
  const fe::JcbbResult r = jcbb.solve(nu.data(), S.data(), m, inlier);
  EXPECT_EQ(r.inlier_count, m - 1);
  EXPECT_EQ(r.rejected_individually, 0);
  EXPECT_TRUE(r.update);
  for (int i = 0; i < m; ++i) {
    EXPECT_EQ(inlier[i], i != periodic) << "landmark " << i;
  }
}
