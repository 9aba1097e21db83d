#include <array>
#include <cmath>
#include <cstddef>
#include <span>

#include "cleanslam/slam_core/camera_frame_measurement.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/frontend/chi_square.hpp"
#include "cleanslam/slam_core/geometry.hpp"

#include <Eigen/Cholesky>

// Where an update is linearized (EkfConfig::solve_pose_beyond_linear_range). The measurement's
// across-ray part is a projection: with the pose uncertain by an angle sigma as seen from the
// landmark, its first-order expansion errs by about sigma^2 / 2, f sigma^2 / 2 pixels. Beyond the
// pixel noise the prior's pose is no place to linearize at: the update is taken from the pose that
// solves the frame's sightings of established landmarks with the prior (the iterated EKF's update,
// Bell and Cathey 1993, relinearized once at that pose).
namespace cleanslam::slam_core {

SightingNoise Ekf::sighting_noise() const {
  SightingNoise n;
  n.eps_ct_m = config_.eps_ct_m;
  n.eps_px = std::hypot(config_.eps_trk_px, config_.eps_cal_px);
  n.focal_px = camera_.focal_px();
  n.min_depth_m = config_.min_depth_m;
  return n;
}

bool Ekf::linearization_pose(const Observation* obs, int count, Vector6d& pose) {
  if (obs == nullptr) {
    return false;
  }
  const SightingNoise noise = sighting_noise();
  const double max_angle_var = 2.0 * noise.eps_px / noise.focal_px;
  const Vector6d prior = x_.head<6>();
  const Matrix6d Ppp = P_.topLeftCorner<6, 6>();
  constexpr std::array<int, 3> kPlanar = {0, 1, 5};
  Eigen::Matrix3d P0;
  for (std::size_t a = 0; a < kPlanar.size(); ++a) {
    for (std::size_t b = 0; b < kPlanar.size(); ++b) {
      P0(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) = Ppp(kPlanar[a], kPlanar[b]);
    }
  }
  const Eigen::LLT<Eigen::Matrix3d> prior_llt(P0);
  if (prior_llt.info() != Eigen::Success) {
    return false;
  }
  // The prior's rotation, shared by all the sightings.
  const Eigen::Matrix3d C_wc = rotation_zyx(prior(3), prior(4), prior(5));
  const RotationZyxDerivatives dC_wc = rotation_zyx_derivatives(prior(3), prior(4), prior(5));
  std::array<int, hal::kMaxObservationsPerFrame> rows{};
  int k = 0;
  bool beyond = false;
  for (int i = 0; i < count && i < hal::kMaxObservationsPerFrame; ++i) {
    const Observation& o = obs[i];
    Eigen::Vector2d n;
    if (!valid_used_slot(o.slot) || young(o.slot) || !std::isfinite(o.u_px) ||
        !std::isfinite(o.v_px) || !camera_.undistort(o.u_px, o.v_px, n)) {
      continue;
    }
    PoseSighting& s = sightings_[static_cast<std::size_t>(k)];
    s.ct = CameraModel::ray(n);
    const int lm = row_of(o.slot);
    s.y = x_.segment<3>(lm);
    const Eigen::Vector3d h = C_wc.transpose() * (s.y - prior.head<3>());  // eq. 21
    const Eigen::Vector3d c = s.ct.normalized();
    const double depth = h.dot(c);
    if (!(h.x() > config_.min_depth_m) || !(depth > config_.min_depth_m)) {
      continue;
    }
    Eigen::Matrix<double, 3, 6> Hp;
    Eigen::Matrix3d Hl;
    measurement_jacobian(C_wc, dC_wc, prior, s.y, Hp, Hl);
    const Eigen::Matrix<double, 3, 6> across =
        (Eigen::Matrix3d::Identity() - c * c.transpose()) * Hp;
    const double angle_var = (across * Ppp * across.transpose()).trace() / (depth * depth);
    beyond = beyond || angle_var > max_angle_var;
    rows[static_cast<std::size_t>(k)] = lm;
    ++k;
  }
  if (!beyond) {
    return false;
  }
  // Each landmark conditioned on the pose's (x, y, yaw).
  for (int j = 0; j < k; ++j) {
    PoseSighting& s = sightings_[static_cast<std::size_t>(j)];
    const int lm = rows[static_cast<std::size_t>(j)];
    Eigen::Matrix3d Pyq;
    for (std::size_t b = 0; b < kPlanar.size(); ++b) {
      Pyq.col(static_cast<Eigen::Index>(b)) = P_.block<3, 1>(lm, kPlanar[b]);
    }
    s.G = prior_llt.solve(Pyq.transpose()).transpose();
    s.Pyy = P_.block<3, 3>(lm, lm) - s.G * Pyq.transpose();
    s.Pyy = 0.5 * (s.Pyy + s.Pyy.transpose()).eval();
  }
  Vector6d solved;
  PoseFit fit;
  if (!solve_planar_pose(
          prior, P0, std::span<const PoseSighting>(sightings_.data(), static_cast<std::size_t>(k)),
          noise, solved, fit)) {
    return false;
  }
  // Only a pose the sightings determine twice over (three or more, two dof each, against its
  // three) and that they fit (chi-square, 99 %) is a better place to linearize at: fewer leave too
  // little redundancy to tell a wrong association or a wrong basin from a pose that moved.
  if (fit.sightings < 3 ||
      !(fit.sightings_cost <= frontend::chi2_quantile_even(2 * fit.sightings, 0.99))) {
    return false;
  }
  // Relinearize only when the solved pose is beyond the prior's linear range: for some sighting
  // the projection's first-order expansion about the prior misses the pixel at the solved pose by
  // more than the pixel noise.
  Vector6d offset = solved - prior;
  offset(3) = wrap_angle(offset(3));
  offset(5) = wrap_angle(offset(5));
  const Eigen::Matrix3d C_wc_solved = rotation_zyx(solved(3), solved(4), solved(5));
  for (int j = 0; j < k; ++j) {
    const PoseSighting& s = sightings_[static_cast<std::size_t>(j)];
    Eigen::Vector2d uv0;
    Eigen::Vector2d uv1;
    Eigen::Matrix<double, 2, 3> J;
    Eigen::Matrix<double, 3, 6> Hp;
    Eigen::Matrix3d Hl;
    const Eigen::Vector3d h0 = C_wc.transpose() * (s.y - prior.head<3>());
    const Eigen::Vector3d h1 = C_wc_solved.transpose() * (s.y - solved.head<3>());
    if (!camera_.project(h0, uv0, &J) || !camera_.project(h1, uv1, nullptr)) {
      pose = solved;
      return true;
    }
    measurement_jacobian(C_wc, dC_wc, prior, s.y, Hp, Hl);
    if ((uv1 - uv0 - J * Hp * offset).norm() > noise.eps_px) {
      pose = solved;
      return true;
    }
  }
  return false;
}

}  // namespace cleanslam::slam_core
