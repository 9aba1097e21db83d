#pragma once

#include <string>
#include <vector>

// Photographs as textures: 8-bit gray images read from a folder (PNG, colour converted to gray),
// each with a mip pyramid (2 x 2 box averages) so that a photograph seen from afar is filtered,
// not aliased.
namespace cleanslam::sim_hal::sim {

class PhotoTextures {
 public:
  // The photographs of the scikit-image sample data the renderer uses, by role.
  static const std::vector<std::string>& file_names();

  // Reads every file of file_names() from `dir`; `missing` gets a line (path: reason) per
  // file that could not be read.
  void load(const std::string& dir, std::vector<std::string>& missing);
  [[nodiscard]] bool complete() const { return !photos_.empty() && missing_ == 0; }
  [[nodiscard]] std::size_t size() const { return photos_.size(); }
  // Aspect ratio (height / width) of photograph `index`.
  [[nodiscard]] double aspect(std::size_t index) const;

  // Brightness in [0, 1] of photograph `index` at (s, t) in [0, 1) (s right, t down), wrapped;
  // `footprint` is the size of the area a sample covers as a fraction of the photograph's width.
  [[nodiscard]] double sample(std::size_t index, double s, double t, double footprint) const;

 private:
  struct Level {
    int width = 0;
    int height = 0;
    std::vector<float> texels;
  };
  std::vector<std::vector<Level>> photos_;
  std::size_t missing_ = 0;
};

}  // namespace cleanslam::sim_hal::sim
