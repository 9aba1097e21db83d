#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cleanslam/hal/image.hpp"
#include "cleanslam/slam_core/frontend/frame_pipeline.hpp"

namespace cleanslam::tools::track {

// An RGB picture of one frame: the image, each search region (gate ellipse, yellow), the
// prediction-to-match line (magenta), inliers (green boxes), outliers (red boxes), searched
// landmarks not found (red cross at the prediction) and new landmarks (cyan boxes).
class Overlay {
 public:
  explicit Overlay(const hal::GrayImageView& image);
  void draw(const slam_core::frontend::FramePipeline& pipeline);
  bool write_png(const std::string& path, std::string& error) const;

 private:
  struct Rgb {
    std::uint8_t r, g, b;
  };
  void pixel(int x, int y, Rgb c);
  void line(double x0, double y0, double x1, double y1, Rgb c);
  void box(double x, double y, int half, Rgb c);
  void cross(double x, double y, int half, Rgb c);
  void ellipse(const slam_core::frontend::SearchRegion& region, Rgb c);

  int width_;
  int height_;
  std::vector<std::uint8_t> rgb_;
};

}  // namespace cleanslam::tools::track
