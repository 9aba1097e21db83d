#include "cleanslam/calibrate/camera_calibration.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include "board_corners.hpp"
#include "cleanslam/calibrate/text.hpp"
#include "view_image.hpp"

namespace cleanslam::calibrate {
namespace {

using CameraResult = readers::Result<CameraCalibration>;

std::string percent(double f) {
  char b[32];
  std::snprintf(b, sizeof b, "%.0f %%", 100.0 * f);
  return b;
}

// The board's inner corners in its own plane, metres, in findChessboardCorners' order.
std::vector<cv::Point3f> board_points(const Checkerboard& b) {
  std::vector<cv::Point3f> p;
  for (int r = 0; r < b.rows; ++r) {
    for (int c = 0; c < b.cols; ++c) {
      p.emplace_back(static_cast<float>(c * b.square_m), static_cast<float>(r * b.square_m), 0.0f);
    }
  }
  return p;
}

// Which edges of the image the corners stay away from (more than a tenth of its size).
std::string edges_missed(const std::array<double, 4>& box, int width, int height) {
  std::vector<std::string> edges;
  if (box[0] > 0.1 * width) {
    edges.emplace_back("left");
  }
  if (box[2] < 0.9 * width) {
    edges.emplace_back("right");
  }
  if (box[1] > 0.1 * height) {
    edges.emplace_back("top");
  }
  if (box[3] < 0.9 * height) {
    edges.emplace_back("bottom");
  }
  std::string s;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    s += (i == 0 ? "" : (i + 1 == edges.size() ? " and " : ", ")) + edges[i];
  }
  return s;
}

}  // namespace

std::vector<std::string> image_files(const std::string& folder) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(folder, ec)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    if (e.is_regular_file() &&
        (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".pgm" || ext == ".bmp")) {
      out.push_back(e.path().string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

CameraResult calibrate_camera(const Views& views, const Checkerboard& board,
                              const CameraCalibrationOptions& o) {
  if (board.cols < 2 || board.rows < 2 || !(board.square_m > 0.0)) {
    return CameraResult::failure(
        "--board, --square: a board of at least 2 x 2 inner corners and a positive "
        "square size is needed");
  }
  CameraCalibration c;
  std::vector<std::vector<cv::Point2f>> corners;
  std::array<double, 4> box{1e300, 1e300, -1e300, -1e300};
  for (std::size_t i = 0; i < views.size(); ++i) {
    const std::string& file = views.name(i);
    const cv::Mat gray = view_image(views, i);
    if (gray.empty()) {
      return CameraResult::failure(file + ": not an image OpenCV can read");
    }
    if (c.images == 0) {
      c.width = gray.cols;
      c.height = gray.rows;
    } else if (gray.cols != c.width || gray.rows != c.height) {
      return CameraResult::failure(file + ": " + std::to_string(gray.cols) + " x " +
                                   std::to_string(gray.rows) + " px, the images before it " +
                                   std::to_string(c.width) + " x " + std::to_string(c.height) +
                                   ": one camera, one size");
    }
    ++c.images;
    std::vector<cv::Point2f> found;
    const bool ok = find_board_corners(gray, board, found);
    if (ok) {
      for (const cv::Point2f& p : found) {
        box = {std::min(box[0], double{p.x}), std::min(box[1], double{p.y}),
               std::max(box[2], double{p.x}), std::max(box[3], double{p.y})};
      }
      corners.push_back(std::move(found));
    } else {
      c.rejected.push_back(file);
    }
    if (o.progress) {
      o.progress(c.images, static_cast<int>(views.size()), file, ok);
    }
  }
  c.views = static_cast<int>(corners.size());
  const std::string board_name =
      std::to_string(board.cols) + " x " + std::to_string(board.rows) + " board";
  if (c.views < o.min_views) {
    std::string s = "the " + board_name + "'s inner corners were found in " +
                    std::to_string(c.views) + " of " + std::to_string(c.images) +
                    " images; at least " + std::to_string(o.min_views) +
                    " views are needed (--min-views)";
    if (!c.rejected.empty()) {
      s += "; not found in:";
      for (const std::string& f : c.rejected) {
        s += " " + f;
      }
    }
    return CameraResult::failure(s +
                                 ". Is --board the inner corners (squares - 1) across and down?");
  }
  c.corner_box = box;
  c.coverage = (box[2] - box[0]) * (box[3] - box[1]) / (double{1.0} * c.width * c.height);
  if (c.coverage < o.min_coverage) {
    char b[160];
    std::snprintf(b, sizeof b, " (x %.0f..%.0f of %d px, y %.0f..%.0f of %d px)", box[0], box[2],
                  c.width, box[1], box[3], c.height);
    return CameraResult::failure(
        "the corners of the " + std::to_string(c.views) + " views cover " + percent(c.coverage) +
        " of the image" + b + ", under --min-coverage " + percent(o.min_coverage) +
        ": the distortion would be guessed at the edges; add views with the board "
        "near the " +
        edges_missed(box, c.width, c.height) + " edge of the image");
  }
  const std::vector<std::vector<cv::Point3f>> object(corners.size(), board_points(board));
  cv::Mat k, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  c.rms_px = cv::calibrateCamera(object, corners, cv::Size(c.width, c.height), k, dist, rvecs,
                                 tvecs, cv::CALIB_FIX_K3);
  c.fx = k.at<double>(0, 0);
  c.fy = k.at<double>(1, 1);
  c.cx = k.at<double>(0, 2);
  c.cy = k.at<double>(1, 2);
  for (int i = 0; i < 4; ++i) {
    c.distortion[static_cast<std::size_t>(i)] = dist.at<double>(i);
  }
  if (c.rms_px > o.max_rms_px) {
    char b[64];
    std::snprintf(b, sizeof b, "%.3f px", c.rms_px);
    return CameraResult::failure(
        std::string("the RMS reprojection error is ") + b +
        ", over --max-rms: " + "blurred images, a board that is not flat, or a wrong --board?");
  }
  return c;
}

CameraCalibration scaled_to(const CameraCalibration& c, int width, int height) {
  CameraCalibration s = c;
  const double sx = static_cast<double>(width) / c.width;
  const double sy = static_cast<double>(height) / c.height;
  s.width = width;
  s.height = height;
  s.fx = c.fx * sx;
  s.fy = c.fy * sy;
  s.cx = (c.cx + 0.5) * sx - 0.5;
  s.cy = (c.cy + 0.5) * sy - 0.5;
  return s;
}

}  // namespace cleanslam::calibrate
