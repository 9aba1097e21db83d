#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "cleanslam/slam_core/camera_frame_measurement.hpp"
#include "cleanslam/slam_core/camera_model.hpp"
#include "cleanslam/slam_core/geometry.hpp"
#include "cleanslam/slam_core/prediction_model.hpp"
#include "numeric_jacobian.hpp"

namespace cs = cleanslam::slam_core;
using cleanslam::test::numeric_jacobian;

namespace {

cs::Vector6d test_pose() {
  cs::Vector6d p;
  p << 0.4, -1.2, 0.15, 0.05, -0.08, 2.3;
  return p;
}

cleanslam::hal::CameraCalibration distorted_camera() {
  cleanslam::hal::CameraCalibration c;
  c.distortion = {-0.28, 0.09, 0.0012, -0.0008};
  return c;
}

}  // namespace

TEST(Geometry, RotationIsZyxAndOrthonormal) {
  const Eigen::Matrix3d R = cs::rotation_zyx(0.3, -0.2, 1.1);
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_LT((R - expected).norm(), 1e-12);
  EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  const Eigen::Vector3d e = cs::euler_zyx_from_rotation(R);
  EXPECT_NEAR(e(0), 0.3, 1e-12);
  EXPECT_NEAR(e(1), -0.2, 1e-12);
  EXPECT_NEAR(e(2), 1.1, 1e-12);
  const Eigen::Quaterniond q = cs::quaternion_from_zyx(0.3, -0.2, 1.1);
  EXPECT_LT((q.toRotationMatrix() - R).norm(), 1e-12);
}

TEST(Geometry, RotationDerivativesMatchNumeric) {
  const Eigen::Vector3d a(0.3, -0.4, 2.0);
  const cs::RotationZyxDerivatives d = cs::rotation_zyx_derivatives(a(0), a(1), a(2));
  const Eigen::Matrix3d* analytic[3] = {&d.d_roll, &d.d_pitch, &d.d_yaw};
  for (int i = 0; i < 3; ++i) {
    Eigen::Vector3d p = a;
    Eigen::Vector3d m = a;
    p(i) += 1e-6;
    m(i) -= 1e-6;
    const Eigen::Matrix3d num =
        (cs::rotation_zyx(p(0), p(1), p(2)) - cs::rotation_zyx(m(0), m(1), m(2))) / 2e-6;
    EXPECT_LT((num - *analytic[i]).norm(), 1e-8) << "angle " << i;
  }
}

TEST(Geometry, EulerRateMatrixIntegratesBodyRates) {
  // A small body-frame rotation applied on the right changes the Euler angles by E * w.
  const double roll = 0.2;
  const double pitch = -0.3;
  const double yaw = 0.7;
  const Eigen::Vector3d w(0.01, -0.02, 0.015);
  const double s = 1e-4;
  const Eigen::Matrix3d R = cs::rotation_zyx(roll, pitch, yaw) *
                            Eigen::AngleAxisd(s * w.norm(), w.normalized()).toRotationMatrix();
  const Eigen::Vector3d e = cs::euler_zyx_from_rotation(R);
  const Eigen::Vector3d rate = (e - Eigen::Vector3d(roll, pitch, yaw)) / s;
  EXPECT_LT((rate - cs::euler_rate_matrix(roll, pitch) * w).norm(), 1e-6);
}

TEST(Geometry, EulerRateJacobianMatchesNumeric) {
  const Eigen::Vector3d w(0.1, -0.2, 0.3);
  const Eigen::Vector2d rp(0.25, -0.35);
  const auto f = [&](const Eigen::Vector2d& x) -> Eigen::Vector3d {
    return cs::euler_rate_matrix(x(0), x(1)) * w;
  };
  const Eigen::Matrix<double, 3, 2> num = numeric_jacobian<3, 2>(f, rp);
  EXPECT_LT((num - cs::euler_rate_matrix_jacobian(rp(0), rp(1), w)).norm(), 1e-8);
}

TEST(Geometry, WrapAngle) {
  constexpr double kPi = std::numbers::pi;
  EXPECT_NEAR(cs::wrap_angle(3.0 * kPi), kPi, 1e-12);
  EXPECT_NEAR(cs::wrap_angle(-kPi + 0.1), -kPi + 0.1, 1e-12);
  EXPECT_NEAR(cs::wrap_angle(7.0), 7.0 - 2.0 * kPi, 1e-12);
}

TEST(CameraModel, DefaultExtrinsicMakesCameraFrameEqualBodyAxes) {
  const cs::CameraModel cam(cleanslam::hal::CameraCalibration{});
  ASSERT_TRUE(cam.valid());
  EXPECT_LT((cam.R_body_c() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(cam.t_body_c().x(), 0.10, 1e-12);
  EXPECT_NEAR(cam.t_body_c().z(), 0.08, 1e-12);
}

TEST(CameraModel, ConvertsOpticalToPaperFrame) {
  const cs::CameraModel cam(cleanslam::hal::CameraCalibration{});
  // A point ahead, to the left and above lands left of and above the principal point.
  Eigen::Vector2d px;
  ASSERT_TRUE(cam.project(Eigen::Vector3d(2.0, 0.5, 0.25), px, nullptr));
  EXPECT_NEAR(px.x(), 159.5 - 280.0 * 0.25, 1e-9);
  EXPECT_NEAR(px.y(), 119.5 - 280.0 * 0.125, 1e-9);
  Eigen::Vector2d n;
  ASSERT_TRUE(cam.undistort(px.x(), px.y(), n));
  const Eigen::Vector3d ct = cs::CameraModel::ray(n);
  EXPECT_LT((ct - Eigen::Vector3d(1.0, 0.25, 0.125)).norm(), 1e-9);
}

TEST(CameraModel, UndistortInvertsDistortion) {
  const cs::CameraModel cam(distorted_camera());
  for (double u : {0.0, 40.0, 159.5, 300.0, 319.0}) {
    for (double v : {0.0, 60.0, 119.5, 239.0}) {
      Eigen::Vector2d n;
      ASSERT_TRUE(cam.undistort(u, v, n)) << u << "," << v;
      Eigen::Vector2d px;
      ASSERT_TRUE(cam.project(Eigen::Vector3d(1.0, -n.x(), -n.y()), px, nullptr));
      EXPECT_NEAR(px.x(), u, 1e-5);
      EXPECT_NEAR(px.y(), v, 1e-5);
    }
  }
}

TEST(CameraModel, RejectsBadPixelsAndPointsBehind) {
  const cs::CameraModel cam(distorted_camera());
  Eigen::Vector2d n;
  EXPECT_FALSE(cam.undistort(std::nan(""), 10.0, n));
  EXPECT_FALSE(cam.undistort(10.0, INFINITY, n));
  EXPECT_FALSE(cam.undistort(-1.0, 10.0, n));
  EXPECT_FALSE(cam.undistort(10.0, 239.6, n));
  EXPECT_TRUE(cam.undistort(-0.5, -0.5, n));
  Eigen::Vector2d px;
  EXPECT_FALSE(cam.project(Eigen::Vector3d(-1.0, 0.0, 0.0), px, nullptr));
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0.0, 1.0, 0.0), px, nullptr));
  EXPECT_FALSE(cam.project(Eigen::Vector3d(1.0, NAN, 0.0), px, nullptr));
  cleanslam::hal::CameraCalibration bad;
  bad.fx = -1.0;
  EXPECT_FALSE(cs::CameraModel(bad).valid());
}

// A camera turned by 0.000865 rad about the body's z axis, written to six decimals: within the
// calibration readers' tolerance (hal::camera_mount_error), so the model takes it.
TEST(CameraModel, AcceptsTheMountsTheCalibrationAccepts) {
  cleanslam::hal::CameraCalibration c;
  c.T_body_cam = {0.000865, 0.0,  1.0, 0.0, -1.0, 0.0, 0.000865, 0.0,
                  0.0,      -1.0, 0.0, 0.0, 0.0,  0.0, 0.0,      1.0};
  ASSERT_EQ(cleanslam::hal::camera_mount_error(c.T_body_cam), nullptr);
  const cs::CameraModel cam(c);
  EXPECT_TRUE(cam.valid());
  Eigen::Vector2d n;
  EXPECT_TRUE(cam.undistort(c.cx, c.cy, n));
  c.T_body_cam[0] = 0.01;  // no longer orthonormal within 1e-4
  ASSERT_NE(cleanslam::hal::camera_mount_error(c.T_body_cam), nullptr);
  EXPECT_FALSE(cs::CameraModel(c).valid());
}

TEST(CameraModel, ProjectionJacobianMatchesNumeric) {
  const cs::CameraModel cam(distorted_camera());
  const Eigen::Vector3d p(2.5, 0.6, -0.4);
  Eigen::Vector2d px;
  Eigen::Matrix<double, 2, 3> J;
  ASSERT_TRUE(cam.project(p, px, &J));
  const auto f = [&](const Eigen::Vector3d& x) -> Eigen::Vector2d {
    Eigen::Vector2d out;
    cam.project(x, out, nullptr);
    return out;
  };
  EXPECT_LT((numeric_jacobian<2, 3>(f, p) - J).norm(), 1e-5);
}

TEST(CameraModel, BodyCameraPoseRoundTrip) {
  cleanslam::hal::CameraCalibration c;
  // Camera tilted up by 10 degrees.
  const double t = 10.0 * std::numbers::pi / 180.0;
  c.T_body_cam = {0.0, std::sin(t),  std::cos(t), 0.10, -1.0, 0.0, 0.0, 0.0,
                  0.0, -std::cos(t), std::sin(t), 0.08, 0.0,  0.0, 0.0, 1.0};
  const cs::CameraModel cam(c);
  ASSERT_TRUE(cam.valid());
  cs::Vector6d body;
  body << 1.0, 2.0, 0.0, 0.0, 0.0, 0.5;
  const cs::Vector6d camera = cs::camera_pose_from_body_pose(body, cam);
  EXPECT_NEAR(camera(4), -t, 1e-9);  // pitch up is negative about y
  EXPECT_NEAR(camera(5), 0.5, 1e-9);
  EXPECT_NEAR(camera(2), 0.08, 1e-9);
  const cs::Vector6d back = cs::body_pose_from_camera_pose(camera, cam);
  EXPECT_LT((back - body).norm(), 1e-9);
}

TEST(CameraFrameMeasurement, RayRotationAlignsXWithRay) {
  for (const Eigen::Vector3d& ct :
       {Eigen::Vector3d(1.0, 0.3, -0.2), Eigen::Vector3d(1.0, -0.5, 0.4),
        Eigen::Vector3d(0.0, 0.0, 1.0)}) {
    const Eigen::Matrix3d M = cs::ray_rotation(ct);
    EXPECT_LT((M.col(0) - ct.normalized()).norm(), 1e-12);
    EXPECT_LT((M.transpose() * M - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  }
}

TEST(CameraFrameMeasurement, CovarianceIsLongAlongTheRay) {
  const Eigen::Vector3d ct(1.0, 0.2, 0.1);
  const double eps_cn = cs::normal_noise(5.0, 0.5, 0.5, 280.0);
  EXPECT_NEAR(eps_cn, std::sqrt(0.5) * 5.0 / 280.0, 1e-15);
  const Eigen::Matrix3d R = cs::measurement_covariance(ct, 30.0, eps_cn);
  const Eigen::Vector3d u = ct.normalized();
  EXPECT_NEAR(u.dot(R * u), 900.0, 1e-9);
  const Eigen::Vector3d across = u.cross(Eigen::Vector3d::UnitZ()).normalized();
  EXPECT_NEAR(across.dot(R * across), eps_cn * eps_cn, 1e-9);
  EXPECT_LT((cs::point_at_depth(ct, 5.0).norm() - 5.0), 1e-12);
}

TEST(CameraFrameMeasurement, MeasurementJacobianMatchesNumeric) {
  const cs::Vector6d pose = test_pose();
  const Eigen::Vector3d y(3.0, -0.5, 1.0);
  Eigen::Matrix<double, 3, 6> Hp;
  Eigen::Matrix3d Hl;
  cs::measurement_jacobian(pose, y, Hp, Hl);
  const auto fp = [&](const cs::Vector6d& x) { return cs::predict_camera_point(x, y); };
  const auto fl = [&](const Eigen::Vector3d& l) { return cs::predict_camera_point(pose, l); };
  EXPECT_LT((numeric_jacobian<3, 6>(fp, pose) - Hp).norm(), 1e-7);
  EXPECT_LT((numeric_jacobian<3, 3>(fl, y) - Hl).norm(), 1e-7);
}

TEST(CameraFrameMeasurement, InitializationJacobianMatchesNumericAndInverts) {
  const cs::Vector6d pose = test_pose();
  const Eigen::Vector3d vc(4.0, 0.7, -0.3);
  Eigen::Matrix<double, 3, 6> T;
  const Eigen::Vector3d y = cs::landmark_from_camera_point(pose, vc, &T);
  const auto f = [&](const cs::Vector6d& x) {
    return cs::landmark_from_camera_point(x, vc, nullptr);
  };
  EXPECT_LT((numeric_jacobian<3, 6>(f, pose) - T).norm(), 1e-7);
  EXPECT_LT((cs::predict_camera_point(pose, y) - vc).norm(), 1e-12);
}

TEST(PredictionModel, JacobiansMatchNumeric) {
  const cs::Vector6d pose = test_pose();
  const Eigen::Vector3d dx(0.12, 0.01, -0.005);
  const Eigen::Vector3d dpsi(0.002, -0.003, 0.08);
  cs::Matrix6d F;
  cs::Matrix6d G;
  cs::prediction_jacobians(pose, dx, dpsi, F, G);
  const auto fx = [&](const cs::Vector6d& x) { return cs::predict_pose(x, dx, dpsi); };
  const auto fu = [&](const cs::Vector6d& u) {
    return cs::predict_pose(pose, u.head<3>(), u.tail<3>());
  };
  cs::Vector6d u;
  u << dx, dpsi;
  EXPECT_LT((numeric_jacobian<6, 6>(fx, pose) - F).norm(), 1e-7);
  EXPECT_LT((numeric_jacobian<6, 6>(fu, u) - G).norm(), 1e-7);
}

TEST(PredictionModel, LevelCameraMovesAlongHeading) {
  cs::Vector6d pose = cs::Vector6d::Zero();
  pose(5) = std::numbers::pi / 2.0;
  const cs::Vector6d out =
      cs::predict_pose(pose, Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d(0.0, 0.0, 0.1));
  EXPECT_NEAR(out(0), 0.0, 1e-12);
  EXPECT_NEAR(out(1), 1.0, 1e-12);
  EXPECT_NEAR(out(5), std::numbers::pi / 2.0 + 0.1, 1e-12);
}
