#pragma once

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "cleanslam/paper_models/landmark_model.hpp"

namespace cleanslam::paper_models {

// EKF update with a pixel measurement (eq. 25-27), Joseph form so that P stays symmetric PSD.
// log_likelihood receives log N(z - h; 0, S).
template <int N>
ModelStatus pixel_update(Eigen::Matrix<double, N, 1>& x, Eigen::Matrix<double, N, N>& P,
                         const Eigen::Vector2d& h, const Eigen::Matrix<double, 2, N>& H,
                         const Eigen::Vector2d& z, double sigma_px, double* log_likelihood) {
  const Eigen::Matrix2d R = Eigen::Matrix2d::Identity() * sigma_px * sigma_px;
  const Eigen::Matrix2d S = H * P * H.transpose() + R;
  const Eigen::LLT<Eigen::Matrix2d> llt(S);
  if (llt.info() != Eigen::Success) {
    return ModelStatus::kSingularInnovation;
  }
  const Eigen::Vector2d innovation = z - h;
  const Eigen::Matrix<double, N, 2> K = llt.solve(H * P).transpose();
  const Eigen::Matrix<double, N, N> I_KH = Eigen::Matrix<double, N, N>::Identity() - K * H;
  x += K * innovation;
  P = I_KH * P * I_KH.transpose() + K * R * K.transpose();
  P = 0.5 * (P + P.transpose()).eval();
  if (log_likelihood != nullptr) {
    const Eigen::Matrix2d L = llt.matrixL();
    const double log_det = 2.0 * (std::log(L(0, 0)) + std::log(L(1, 1)));
    const double mahalanobis = innovation.dot(llt.solve(innovation));
    constexpr double kLog2Pi = 1.8378770664093453;
    *log_likelihood = -0.5 * (mahalanobis + log_det) - kLog2Pi;
  }
  return ModelStatus::kOk;
}

}  // namespace cleanslam::paper_models
