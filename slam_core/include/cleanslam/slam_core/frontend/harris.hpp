#pragma once

#include <array>
#include <memory>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/image.hpp"
#include "cleanslam/slam_core/frontend/image_check.hpp"

namespace cleanslam::slam_core::frontend {

struct Corner {
  double x = 0.0;  // pixel column, origin at the centre of the top-left pixel
  double y = 0.0;
  float response = 0.0F;
};

// Harris and Stephens (1988), Section 3.2 of the paper.
struct HarrisConfig {
  float k = 0.04F;
  // Standard deviation of the Gaussian weights of the structure tensor, in pixels (<= 1.5).
  float sigma_px = 1.0F;
  // A corner's response must exceed quality_level times the frame's strongest response...
  float quality_level = 0.01F;
  // ...and this absolute floor (Sobel gradients, so roughly (gray levels * 8)^4): a textureless
  // or saturated frame yields no corner.
  float min_response = 1.0e6F;
  // Accepted corners are at least this far apart (strongest first).
  float min_distance_px = 5.0F;
  // Corners are kept at least this far from the image border.
  int border_px = 8;
  // At most this many corners (<= hal::kMaxCorners).
  int max_corners = hal::kMaxCorners;
};

// Gradients (Sobel), the Gaussian-weighted structure tensor, the response det - k trace^2,
// 3x3 non-maximum suppression, thresholds, strongest first with a minimum distance. All buffers
// are sized by hal::kImageWidth x hal::kImageHeight and allocated at construction.
class HarrisDetector {
 public:
  explicit HarrisDetector(const HarrisConfig& config = {});
  ~HarrisDetector();
  HarrisDetector(const HarrisDetector&) = delete;
  HarrisDetector& operator=(const HarrisDetector&) = delete;

  // Detects the corners of `image`, which must be width x height (check_image); writes them into
  // the detector's list, strongest first. Returns the check; on failure the list is empty.
  ImageCheck detect(const hal::GrayImageView& image, int width, int height);

  // The same detection in bounded pieces for the cooperative loop: begin() checks the image
  // (which must stay valid until step() returns true); each step() processes up to max_rows
  // image rows, and the last one also selects the corners.
  ImageCheck begin(const hal::GrayImageView& image, int width, int height);
  bool step(int max_rows);
  [[nodiscard]] bool finished() const { return finished_; }

  [[nodiscard]] const Corner* corners() const { return corners_.data(); }
  [[nodiscard]] int corner_count() const { return corner_count_; }
  [[nodiscard]] const HarrisConfig& config() const { return config_; }
  // Strongest response of the last frame (0 for a flat frame).
  [[nodiscard]] float max_response() const { return max_response_; }

  // Working buffers (implementation detail, public for the row kernels).
  struct Planes;

 private:
  void suppress_rows(int last_response_row);
  void select_corners();

  HarrisConfig config_;
  std::array<float, 7> kernel_{};
  int kernel_radius_ = 2;
  std::unique_ptr<Planes> planes_;
  std::array<Corner, hal::kMaxCorners> corners_{};
  int corner_count_ = 0;
  float max_response_ = 0.0F;
  hal::GrayImageView image_;
  int next_row_ = 0;
  int nms_row_ = 0;
  int candidate_count_ = 0;
  bool finished_ = true;
};

}  // namespace cleanslam::slam_core::frontend
