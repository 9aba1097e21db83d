#pragma once

#include <Eigen/Dense>

#include "cleanslam/slam_core/camera_frame_measurement.hpp"
#include "cleanslam/slam_core/ekf.hpp"

namespace cleanslam::test {

// The m observations stacked densely at the EKF's current state (eq. 10-23): innovations nu
// (3m), noise R (3m x 3m) and the full Jacobian H (3m x active_dim), the textbook reference for
// the batch update. False when a pixel cannot be undistorted.
inline bool stack_observations(const slam_core::Ekf& ekf, const slam_core::Observation* obs, int m,
                               Eigen::VectorXd& nu, Eigen::MatrixXd& R, Eigen::MatrixXd& H) {
  namespace cs = slam_core;
  const int n = ekf.active_dim();
  const Eigen::VectorXd x = ekf.state().head(n);
  const cs::EkfConfig& c = ekf.config();
  H = Eigen::MatrixXd::Zero(3 * m, n);
  R = Eigen::MatrixXd::Zero(3 * m, 3 * m);
  nu.resize(3 * m);
  for (int i = 0; i < m; ++i) {
    const cs::Observation& o = obs[i];
    Eigen::Vector2d nrm;
    if (!ekf.camera().undistort(o.u_px, o.v_px, nrm)) {
      return false;
    }
    const Eigen::Vector3d ct = cs::CameraModel::ray(nrm);
    const Eigen::Vector3d y = x.segment<3>(6 + 3 * o.slot);
    const Eigen::Vector3d h = cs::predict_camera_point(x.head<6>(), y);
    const double d = h.dot(ct.normalized());
    nu.segment<3>(3 * i) = cs::point_at_depth(ct, d) - h;
    R.block<3, 3>(3 * i, 3 * i) = cs::measurement_covariance(
        ct, c.eps_ct_m, cs::normal_noise(d, c.eps_trk_px, c.eps_cal_px, 280.0));
    Eigen::Matrix<double, 3, 6> Hp;
    Eigen::Matrix3d Hl;
    cs::measurement_jacobian(x.head<6>(), y, Hp, Hl);
    H.block<3, 6>(3 * i, 0) = Hp;
    H.block<3, 3>(3 * i, 6 + 3 * o.slot) = Hl;
  }
  return true;
}

}  // namespace cleanslam::test
