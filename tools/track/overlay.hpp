#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cleanslam/hal/image.hpp"
#include "cleanslam/slam_core/frontend/frame_pipeline.hpp"

namespace cleanslam::tools::track {

// What the caption says of a frame: its number in the run and its time in the dataset.
struct FrameCaption {
  long frame = 0;
  double t_s = 0.0;
};

// An RGB picture of one frame, enlarged twice when the image is small: the image, each search
// region (gate ellipse, yellow), the prediction-to-match line (magenta), inliers (green boxes),
// outliers (red boxes), searched landmarks not found (red cross at the prediction) and new
// landmarks (cyan boxes); below it a strip with the frame's number, time and counts, and a
// legend of the marks.
class Overlay {
 public:
  struct Rgb {
    std::uint8_t r, g, b;
  };
  explicit Overlay(const hal::GrayImageView& image);
  void draw(const slam_core::frontend::FramePipeline& pipeline, const FrameCaption& caption);
  bool write_png(const std::string& path, std::string& error) const;
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  // The picture's pixel; the caption strip starts at image_height().
  [[nodiscard]] Rgb at(int x, int y) const;
  [[nodiscard]] int image_height() const { return image_height_; }

 private:
  enum class Mark { kRegion, kShift, kInlier, kOutlier, kNotFound, kNew };
  void pixel(int x, int y, Rgb c);
  // Canvas coordinates.
  void line(double x0, double y0, double x1, double y1, Rgb c);
  void box(double x, double y, double half, Rgb c);
  void cross(double x, double y, double half, Rgb c);
  void mark(Mark m, double x, double y);
  void text(int x, int y, const std::string& s, Rgb c);
  // Image coordinates.
  [[nodiscard]] double canvas(double image_px) const;
  void ellipse(const slam_core::frontend::SearchRegion& region, Rgb c);
  void strip(const slam_core::frontend::FrameReport& report, const FrameCaption& caption);

  int scale_;
  int image_height_;
  int width_;
  int height_;
  std::vector<std::uint8_t> rgb_;
};

}  // namespace cleanslam::tools::track
