#pragma once

#include <array>
#include <cstddef>
#include <memory>

#include <Eigen/Core>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/image.hpp"

namespace cleanslam::slam_core::frontend {

// The 15x15 matching window of Section 3.4.
inline constexpr int kPatchRadius = 7;
inline constexpr int kPatchSize = 2 * kPatchRadius + 1;
// What is kept from the first sighting: a larger window, so that the patch can be resampled at
// scales down to kMinPatchScale (the landmark seen from farther away) with the one-pixel border
// the template gradients need.
inline constexpr int kStoredPatchRadius = 15;
inline constexpr int kStoredPatchSize = 2 * kStoredPatchRadius + 1;
inline constexpr double kMinPatchScale = 0.6;
inline constexpr double kMaxPatchScale = 3.0;

// Index of pixel (row r, column c) of a row-major window `cols` pixels wide; r, c >= 0.
[[nodiscard]] constexpr std::size_t pixel_index(int r, int c, int cols) {
  return static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(c);
}

// A landmark's appearance at its first sighting, centred on the sub-pixel corner, with the
// landmark's depth at that time (Section 3.4, feature-scale prediction).
struct LandmarkPatch {
  std::array<float, std::size_t{kStoredPatchSize} * kStoredPatchSize> pixels{};
  double first_depth_m = 0.0;
  // Where the camera was at the first sighting (when the estimator tells): the scale is then the
  // landmark's current distance estimate from there over its distance from the camera now, which
  // stays right as the landmark's depth converges (the depth assumed at initialization does not).
  std::array<double, 3> anchor{};
  bool has_anchor = false;
  bool valid = false;
};

// Samples the stored window around (u, v) bilinearly. False (patch left invalid) when the window
// does not fit inside the image or the depth is not finite and positive.
bool capture_patch(const hal::GrayImageView& image, double u_px, double v_px, double depth_m,
                   LandmarkPatch& out);

// Scale of the landmark's image now relative to its first sighting: first depth / predicted
// depth (pinhole: size ~ 1/depth), clamped to [kMinPatchScale, kMaxPatchScale]; 1 when either
// depth is not usable.
[[nodiscard]] double predicted_patch_scale(double first_depth_m, double predicted_depth_m);

// The template a tracker matches: the first-sighting patch resampled at the predicted scale,
// zero-mean, with its gradients and the inverse of the 2x2 Gauss-Newton Hessian of the
// inverse-compositional Lucas-Kanade (Baker and Matthews 2004).
struct PatchTemplate {
  std::array<float, std::size_t{kPatchSize} * kPatchSize> zero_mean{};
  std::array<float, std::size_t{kPatchSize} * kPatchSize> gx{};
  std::array<float, std::size_t{kPatchSize} * kPatchSize> gy{};
  float sum_sq = 0.0F;  // sum of zero_mean^2
  // Sums that let the tracker's single pass over the window form the zero-mean residual.
  float sum_gx = 0.0F;
  float sum_gy = 0.0F;
  float sum_gx_t = 0.0F;
  float sum_gy_t = 0.0F;
  float sum_t = 0.0F;
  float h_inv_xx = 0.0F;
  float h_inv_xy = 0.0F;
  float h_inv_yy = 0.0F;
  // Smaller over larger eigenvalue of the Hessian: near 0 for an edge (the aperture problem: the
  // match slides along it), 1 for an isotropic corner.
  float isotropy = 0.0F;
  double scale = 1.0;
  bool valid = false;
};

// Builds the template at `scale` (already clamped by predicted_patch_scale). Invalid when the
// patch is invalid or too flat to track (standard deviation below min_std_gray, or a singular
// Hessian).
bool make_template(const LandmarkPatch& patch, double scale, float min_std_gray,
                   PatchTemplate& out);

// One patch per landmark slot, allocated at construction.
class PatchStore {
 public:
  PatchStore();
  ~PatchStore();
  PatchStore(const PatchStore&) = delete;
  PatchStore& operator=(const PatchStore&) = delete;

  // False for a slot out of range or a window that does not fit (the slot is then cleared).
  bool capture(int slot, const hal::GrayImageView& image, double u_px, double v_px, double depth_m);
  void clear(int slot);
  // Records the camera position of the slot's first sighting (LandmarkPatch::anchor).
  void set_anchor(int slot, const Eigen::Vector3d& camera_position);
  // Null for a slot out of range or without a patch.
  [[nodiscard]] const LandmarkPatch* get(int slot) const;

 private:
  std::unique_ptr<std::array<LandmarkPatch, hal::kMaxLandmarks>> patches_;
};

}  // namespace cleanslam::slam_core::frontend
