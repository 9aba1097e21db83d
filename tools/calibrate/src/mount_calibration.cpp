#include "cleanslam/calibrate/mount_calibration.hpp"

#include <cmath>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "board_corners.hpp"
#include "cleanslam/calibrate/text.hpp"
#include "view_image.hpp"

namespace cleanslam::calibrate {
namespace {

using MountResult = readers::Result<MountCalibration>;

// The four ways findChessboardCorners may have ordered the corners: as laid, turned half round,
// and the two mirror images (which no rotation fits: their error tells them apart).
std::vector<cv::Point2f> reordered(const std::vector<cv::Point2f>& found, const Checkerboard& b,
                                   int way) {
  std::vector<cv::Point2f> out(found.size());
  for (int r = 0; r < b.rows; ++r) {
    for (int c = 0; c < b.cols; ++c) {
      const int rr = (way & 1) ? b.rows - 1 - r : r;
      const int cc = (way & 2) ? b.cols - 1 - c : c;
      out[static_cast<std::size_t>(r * b.cols + c)] =
          found[static_cast<std::size_t>(rr * b.cols + cc)];
    }
  }
  return out;
}

}  // namespace

std::vector<std::array<double, 3>> board_corners_on_floor(const Checkerboard& b,
                                                          const BoardOnFloor& spot) {
  std::vector<std::array<double, 3>> out;
  const double cy = std::cos(spot.yaw_rad), sy = std::sin(spot.yaw_rad);
  for (int r = 0; r < b.rows; ++r) {
    for (int c = 0; c < b.cols; ++c) {
      const double bx = (c - 0.5 * (b.cols - 1)) * b.square_m;
      const double by = (r - 0.5 * (b.rows - 1)) * b.square_m;
      out.push_back({spot.x_m + cy * bx - sy * by, spot.y_m + sy * bx + cy * by, 0.0});
    }
  }
  return out;
}

MountResult calibrate_mount(const Views& images, const Checkerboard& board,
                            const BoardOnFloor& spot, const hal::CameraCalibration& camera,
                            double max_rms_px) {
  if (images.empty()) {
    return MountResult::failure("no images of the board on the floor");
  }
  std::vector<cv::Point3f> body_points;
  for (const auto& p : board_corners_on_floor(board, spot)) {
    body_points.emplace_back(static_cast<float>(p[0]), static_cast<float>(p[1]),
                             static_cast<float>(p[2]));
  }
  std::vector<std::vector<cv::Point2f>> views;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const std::string& file = images.name(i);
    const cv::Mat gray = view_image(images, i);
    if (gray.empty()) {
      return MountResult::failure(file + ": not an image OpenCV can read");
    }
    std::vector<cv::Point2f> found;
    if (!find_board_corners(gray, board, found)) {
      return MountResult::failure(file + ": the " + std::to_string(board.cols) + " x " +
                                  std::to_string(board.rows) +
                                  " board's inner corners are not found: is it wholly in view?");
    }
    views.push_back(std::move(found));
  }
  // A still robot and board: every view in the first one's order.
  for (auto& v : views) {
    double least = 1e300;
    std::vector<cv::Point2f> closest;
    for (int way = 0; way < 4; ++way) {
      std::vector<cv::Point2f> o = reordered(v, board, way);
      double d = 0.0;
      for (std::size_t i = 0; i < o.size(); ++i) {
        d += cv::norm(o[i] - views.front()[i]);
      }
      if (d < least) {
        least = d;
        closest = std::move(o);
      }
    }
    v = std::move(closest);
  }
  const cv::Matx33d k(camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0);
  const cv::Vec4d dist(camera.distortion[0], camera.distortion[1], camera.distortion[2],
                       camera.distortion[3]);
  // The corners fit four poses about equally: the board's corners are the same under a half turn
  // (a camera as far beyond the board), and a mirrored order fits a camera below the floor. The
  // camera is above the floor, and the nearer to the body's origin of the other two is on the
  // robot.
  double best_rms = 1e300, best_distance = 1e300;
  cv::Vec3d best_r, best_t;
  for (int way = 0; way < 4; ++way) {
    std::vector<cv::Point3f> object;
    std::vector<cv::Point2f> image;
    for (const auto& v : views) {
      object.insert(object.end(), body_points.begin(), body_points.end());
      const auto ordered = reordered(v, board, way);
      image.insert(image.end(), ordered.begin(), ordered.end());
    }
    cv::Vec3d r, t;
    if (!cv::solvePnP(object, image, k, dist, r, t)) {
      continue;
    }
    cv::Matx33d rotation;
    cv::Rodrigues(r, rotation);
    const cv::Vec3d centre = -(rotation.t() * t);
    if (centre[2] <= 0.0) {
      continue;
    }
    std::vector<cv::Point2f> projected;
    cv::projectPoints(object, r, t, k, dist, projected);
    double ss = 0.0;
    for (std::size_t i = 0; i < image.size(); ++i) {
      const cv::Point2f d = projected[i] - image[i];
      ss += double{d.x} * double{d.x} + double{d.y} * double{d.y};
    }
    const double rms = std::sqrt(ss / static_cast<double>(image.size()));
    if (rms <= max_rms_px && cv::norm(centre) < best_distance) {
      best_distance = cv::norm(centre);
      best_rms = rms;
      best_r = r;
      best_t = t;
    } else if (best_distance == 1e300 && rms < best_rms) {
      best_rms = rms;  // for the message when nothing fits
    }
  }
  if (best_distance == 1e300) {
    return MountResult::failure(
        "the board's corners at the given spot reproject " + fixed(best_rms, 2) +
        " px RMS from where they are seen, over " + fixed(max_rms_px, 1) +
        " px (--max-rms): are the intrinsics this camera's, and the board flat?");
  }
  // solvePnP gives the body in the camera (p_cam = R p_body + t); the mount is its inverse.
  cv::Matx33d r_cam_body;
  cv::Rodrigues(best_r, r_cam_body);
  const cv::Matx33d r_body_cam = r_cam_body.t();
  const cv::Vec3d t_body_cam = -(r_body_cam * best_t);
  MountCalibration m;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      m.T_body_cam[static_cast<std::size_t>(4 * i + j)] = r_body_cam(i, j);
    }
    m.T_body_cam[static_cast<std::size_t>(4 * i + 3)] = t_body_cam[i];
  }
  m.T_body_cam[15] = 1.0;
  m.rms_px = best_rms;
  m.views = static_cast<int>(views.size());
  m.height_m = t_body_cam[2];
  // The optical axis (the camera's z) in the body frame.
  const double ax = r_body_cam(0, 2), ay = r_body_cam(1, 2), az = r_body_cam(2, 2);
  constexpr double kDeg = 180.0 / std::numbers::pi;
  m.tilt_deg = std::atan2(az, std::hypot(ax, ay)) * kDeg;
  m.yaw_deg = std::atan2(ay, ax) * kDeg;
  return m;
}

}  // namespace cleanslam::calibrate
