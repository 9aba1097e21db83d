#include "cleanslam/slam_core/pose_solve.hpp"

#include <cmath>

#include <Eigen/Cholesky>

#include "cleanslam/slam_core/camera_frame_measurement.hpp"
#include "cleanslam/slam_core/geometry.hpp"

namespace cleanslam::slam_core {

namespace {
constexpr int kYaw = 5;

Vector6d planar_step(const Vector6d& pose, const Eigen::Vector3d& d) {
  Vector6d out = pose;
  out(0) += d(0);
  out(1) += d(1);
  out(kYaw) = wrap_angle(out(kYaw) + d(2));
  return out;
}

Eigen::Vector3d planar_difference(const Vector6d& a, const Vector6d& b) {
  return {a(0) - b(0), a(1) - b(1), wrap_angle(a(kYaw) - b(kYaw))};
}

// A pose's M_wc and its derivatives, computed once for all the sightings seen from it.
struct PoseRotation {
  PoseRotation(const Vector6d& pose, bool with_derivatives)
      : C_wc(rotation_zyx(pose(3), pose(4), pose(kYaw))) {
    if (with_derivatives) {
      dC_wc = rotation_zyx_derivatives(pose(3), pose(4), pose(kYaw));
    }
  }
  Eigen::Matrix3d C_wc;
  RotationZyxDerivatives dC_wc;  // when asked for
};

// sighting_residual with the pose's rotation given.
Eigen::Vector3d residual_at(const PoseRotation& R, const Vector6d& pose, const Eigen::Vector3d& y,
                            const Eigen::Vector3d& ct, Eigen::Matrix3d* J_planar,
                            Eigen::Matrix3d* J_landmark) {
  const Eigen::Vector3d c = ct.normalized();
  const Eigen::Matrix3d across = c * c.transpose() - Eigen::Matrix3d::Identity();
  if (J_planar != nullptr || J_landmark != nullptr) {
    Eigen::Matrix<double, 3, 6> Hp;
    Eigen::Matrix3d Hl;
    measurement_jacobian(R.C_wc, R.dC_wc, pose, y, Hp, Hl);  // eq. 22-24
    if (J_planar != nullptr) {
      J_planar->col(0) = across * Hp.col(0);
      J_planar->col(1) = across * Hp.col(1);
      J_planar->col(2) = across * Hp.col(kYaw);
    }
    if (J_landmark != nullptr) {
      *J_landmark = across * Hl;
    }
  }
  return across * (R.C_wc.transpose() * (y - pose.head<3>()));
}

// sighting_covariance with the pose's rotation C_wc given (computed once per pose).
bool sighting_covariance_at(const Eigen::Matrix3d& C_wc, const Vector6d& pose,
                            const Eigen::Vector3d& y, const PoseSighting& s,
                            const SightingNoise& noise, Eigen::Matrix3d& S) {
  const Eigen::Matrix3d C_cw = C_wc.transpose();
  const Eigen::Vector3d h = C_cw * (y - pose.head<3>());
  const double depth = h.dot(s.ct.normalized());
  if (!(h.x() > noise.min_depth_m) || !(depth > noise.min_depth_m)) {
    return false;
  }
  S = C_cw * s.Pyy * C_cw.transpose() +
      measurement_covariance(s.ct, noise.eps_ct_m, depth * noise.eps_px / noise.focal_px);
  S = 0.5 * (S + S.transpose()).eval();
  return S.allFinite();
}

// The cost at pose, each sighting weighted by S_j^-1 at weight_pose (held while a step is tried: a
// cost whose weights moved with the pose would favour poses that make its sightings noisier), and
// with A and b its Gauss-Newton normal equations (a tried step needs the cost alone); false when no
// sighting is ahead of the camera at both or a weight is not positive definite.
bool normal_equations(const Vector6d& pose, const Vector6d& weight_pose, const Vector6d& prior,
                      const Eigen::Matrix3d& info0, std::span<const PoseSighting> sightings,
                      const SightingNoise& noise, Eigen::Matrix3d* A, Eigen::Vector3d* b,
                      double& cost, PoseFit& fit) {
  const Eigen::Vector3d d0 = planar_difference(pose, prior);
  if (A != nullptr && b != nullptr) {
    *A = info0;
    *b = -info0 * d0;
  }
  fit.prior_cost = d0.dot(info0 * d0);
  fit.sightings_cost = 0.0;
  const bool weights_here = pose == weight_pose;
  const PoseRotation R(pose, A != nullptr && b != nullptr);
  const Eigen::Matrix3d& C_wc = R.C_wc;
  const Eigen::Matrix3d C_wc_weights =
      weights_here ? C_wc : rotation_zyx(weight_pose(3), weight_pose(4), weight_pose(kYaw));
  int used = 0;
  for (const PoseSighting& s : sightings) {
    const Eigen::Vector3d y = conditional_landmark(s, prior, pose);
    Eigen::Matrix3d S;
    if (!sighting_covariance_at(C_wc, pose, y, s, noise, S) ||
        (!weights_here &&
         !sighting_covariance_at(C_wc_weights, weight_pose,
                                 conditional_landmark(s, prior, weight_pose), s, noise, S))) {
      continue;
    }
    const Eigen::LLT<Eigen::Matrix3d> llt(S);
    if (llt.info() != Eigen::Success) {
      return false;
    }
    Eigen::Matrix3d Jq;
    Eigen::Matrix3d Jy;
    const bool jacobians = A != nullptr && b != nullptr;
    const Eigen::Vector3d r =
        residual_at(R, pose, y, s.ct, jacobians ? &Jq : nullptr, jacobians ? &Jy : nullptr);
    if (jacobians) {
      const Eigen::Matrix3d J = Jq + Jy * s.G;
      const Eigen::Matrix3d WJ = llt.solve(J);
      A->noalias() += J.transpose() * WJ;
      b->noalias() -= WJ.transpose() * r;
    }
    fit.sightings_cost += r.dot(llt.solve(r));
    ++used;
  }
  fit.sightings = used;
  cost = fit.prior_cost + fit.sightings_cost;
  const bool finite = A == nullptr || b == nullptr || (A->allFinite() && b->allFinite());
  return used > 0 && finite && std::isfinite(cost);
}
}  // namespace

Eigen::Vector3d sighting_residual(const Vector6d& pose, const Eigen::Vector3d& y,
                                  const Eigen::Vector3d& ct, Eigen::Matrix3d* J_planar,
                                  Eigen::Matrix3d* J_landmark) {
  const bool jacobians = J_planar != nullptr || J_landmark != nullptr;
  return residual_at(PoseRotation(pose, jacobians), pose, y, ct, J_planar, J_landmark);
}

Eigen::Vector3d conditional_landmark(const PoseSighting& s, const Vector6d& prior_pose,
                                     const Vector6d& pose) {
  return s.y + s.G * planar_difference(pose, prior_pose);
}

bool sighting_covariance(const Vector6d& pose, const Eigen::Vector3d& y, const PoseSighting& s,
                         const SightingNoise& noise, Eigen::Matrix3d& S) {
  return sighting_covariance_at(rotation_zyx(pose(3), pose(4), pose(kYaw)), pose, y, s, noise, S);
}

bool solve_planar_pose(const Vector6d& prior_pose, const Eigen::Matrix3d& P0,
                       std::span<const PoseSighting> sightings, const SightingNoise& noise,
                       Vector6d& pose, PoseFit& fit, int max_iterations) {
  const Eigen::LLT<Eigen::Matrix3d> prior_llt(P0);
  if (prior_llt.info() != Eigen::Success || !prior_pose.allFinite()) {
    return false;
  }
  const Eigen::Matrix3d info0 = prior_llt.solve(Eigen::Matrix3d::Identity());
  Vector6d p = prior_pose;
  Eigen::Matrix3d A;
  Eigen::Vector3d b;
  double cost = 0.0;
  if (!normal_equations(p, p, prior_pose, info0, sightings, noise, &A, &b, cost, fit)) {
    return false;
  }
  for (int it = 0; it < max_iterations; ++it) {
    const Eigen::LLT<Eigen::Matrix3d> llt(A);
    if (llt.info() != Eigen::Success) {
      return false;
    }
    const Eigen::Vector3d full = llt.solve(b);
    // Halve a step that does not lower the cost (weighted as at p).
    bool lowered = false;
    Eigen::Vector3d step = full;
    for (int h = 0; h < 10 && !lowered; ++h) {
      step = std::ldexp(1.0, -h) * full;
      const Vector6d q = planar_step(p, step);
      double cq = 0.0;
      PoseFit fq;
      if (normal_equations(q, p, prior_pose, info0, sightings, noise, nullptr, nullptr, cq, fq) &&
          cq < cost &&
          normal_equations(q, q, prior_pose, info0, sightings, noise, &A, &b, cost, fit)) {
        lowered = true;
        p = q;
      }
    }
    if (!lowered || step.head<2>().norm() < 1e-7) {
      break;
    }
  }
  if (!p.allFinite()) {
    return false;
  }
  pose = p;
  return true;
}

}  // namespace cleanslam::slam_core
