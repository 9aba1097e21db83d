#include "cleanslam/slam_core/frontend/patch.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace cleanslam::slam_core::frontend {

namespace {

constexpr int kTemplateSide = kPatchSize + 2;  // one-pixel border for central differences

float sample_stored(const LandmarkPatch& p, float x, float y) {
  // (x, y) relative to the patch centre; callers keep it inside the stored window.
  const float fx = x + static_cast<float>(kStoredPatchRadius);
  const float fy = y + static_cast<float>(kStoredPatchRadius);
  const int ix = std::clamp(static_cast<int>(std::floor(fx)), 0, kStoredPatchSize - 2);
  const int iy = std::clamp(static_cast<int>(std::floor(fy)), 0, kStoredPatchSize - 2);
  const float ax = fx - static_cast<float>(ix);
  const float ay = fy - static_cast<float>(iy);
  const float* r0 = p.pixels.data() + pixel_index(iy, ix, kStoredPatchSize);
  const float* r1 = r0 + kStoredPatchSize;
  const float top = r0[0] + ax * (r0[1] - r0[0]);
  const float bot = r1[0] + ax * (r1[1] - r1[0]);
  return top + ay * (bot - top);
}

}  // namespace

bool capture_patch(const hal::GrayImageView& image, double u_px, double v_px, double depth_m,
                   LandmarkPatch& out) {
  out.valid = false;
  if (image.empty() || !std::isfinite(u_px) || !std::isfinite(v_px) || !std::isfinite(depth_m) ||
      depth_m <= 0.0) {
    return false;
  }
  const double left = u_px - kStoredPatchRadius;
  const double top = v_px - kStoredPatchRadius;
  if (left < 0.0 || top < 0.0 || u_px + kStoredPatchRadius + 1.0 > image.width - 1 ||
      v_px + kStoredPatchRadius + 1.0 > image.height - 1) {
    return false;
  }
  const int ix = static_cast<int>(std::floor(left));
  const int iy = static_cast<int>(std::floor(top));
  const auto ax = static_cast<float>(left - ix);
  const auto ay = static_cast<float>(top - iy);
  const float w00 = (1.0F - ax) * (1.0F - ay);
  const float w01 = ax * (1.0F - ay);
  const float w10 = (1.0F - ax) * ay;
  const float w11 = ax * ay;
  for (int r = 0; r < kStoredPatchSize; ++r) {
    const std::uint8_t* a = image.row(iy + r) + ix;
    const std::uint8_t* b = image.row(iy + r + 1) + ix;
    float* dst = out.pixels.data() + pixel_index(r, 0, kStoredPatchSize);
    for (int c = 0; c < kStoredPatchSize; ++c) {
      dst[c] = w00 * static_cast<float>(a[c]) + w01 * static_cast<float>(a[c + 1]) +
               w10 * static_cast<float>(b[c]) + w11 * static_cast<float>(b[c + 1]);
    }
  }
  out.first_depth_m = depth_m;
  out.has_anchor = false;
  out.valid = true;
  return true;
}

double predicted_patch_scale(double first_depth_m, double predicted_depth_m) {
  if (!std::isfinite(first_depth_m) || !std::isfinite(predicted_depth_m) || first_depth_m <= 0.0 ||
      predicted_depth_m <= 0.0) {
    return 1.0;
  }
  return std::clamp(first_depth_m / predicted_depth_m, kMinPatchScale, kMaxPatchScale);
}

bool make_template(const LandmarkPatch& patch, double scale, float min_std_gray,
                   PatchTemplate& out) {
  out.valid = false;
  if (!patch.valid || !std::isfinite(scale)) {
    return false;
  }
  const double s = std::clamp(scale, kMinPatchScale, kMaxPatchScale);
  out.scale = s;
  const auto inv = static_cast<float>(1.0 / s);
  std::array<float, std::size_t{kTemplateSide} * kTemplateSide> t{};
  constexpr int kHalf = kTemplateSide / 2;
  // Shrinking (s < 1) averages four samples a quarter of the source spacing apart, so that the
  // coarser sampling does not alias.
  const bool smooth = s < 0.9;
  const float q = 0.25F * inv;
  for (int r = 0; r < kTemplateSide; ++r) {
    const float y = static_cast<float>(r - kHalf) * inv;
    for (int c = 0; c < kTemplateSide; ++c) {
      const float x = static_cast<float>(c - kHalf) * inv;
      float v = 0.0F;
      if (smooth) {
        v = 0.25F * (sample_stored(patch, x - q, y - q) + sample_stored(patch, x + q, y - q) +
                     sample_stored(patch, x - q, y + q) + sample_stored(patch, x + q, y + q));
      } else {
        v = sample_stored(patch, x, y);
      }
      t[pixel_index(r, c, kTemplateSide)] = v;
    }
  }
  float sum = 0.0F;
  for (int r = 1; r <= kPatchSize; ++r) {
    for (int c = 1; c <= kPatchSize; ++c) {
      sum += t[pixel_index(r, c, kTemplateSide)];
    }
  }
  const float mean = sum / static_cast<float>(kPatchSize * kPatchSize);
  float ss = 0.0F;
  float hxx = 0.0F;
  float hxy = 0.0F;
  float hyy = 0.0F;
  for (int r = 1; r <= kPatchSize; ++r) {
    for (int c = 1; c <= kPatchSize; ++c) {
      const std::size_t i = pixel_index(r, c, kTemplateSide);
      const std::size_t o = pixel_index(r - 1, c - 1, kPatchSize);
      const float z = t[i] - mean;
      const float gx = 0.5F * (t[i + 1] - t[i - 1]);
      const float gy = 0.5F * (t[i + kTemplateSide] - t[i - kTemplateSide]);
      out.zero_mean[o] = z;
      out.gx[o] = gx;
      out.gy[o] = gy;
      ss += z * z;
      hxx += gx * gx;
      hxy += gx * gy;
      hyy += gy * gy;
    }
  }
  out.sum_sq = ss;
  float sgx = 0.0F;
  float sgy = 0.0F;
  float sgxt = 0.0F;
  float sgyt = 0.0F;
  float st = 0.0F;
  for (std::size_t i = 0; i < out.zero_mean.size(); ++i) {
    sgx += out.gx[i];
    sgy += out.gy[i];
    sgxt += out.gx[i] * out.zero_mean[i];
    sgyt += out.gy[i] * out.zero_mean[i];
    st += out.zero_mean[i];
  }
  out.sum_gx = sgx;
  out.sum_gy = sgy;
  out.sum_gx_t = sgxt;
  out.sum_gy_t = sgyt;
  out.sum_t = st;
  const float min_ss = min_std_gray * min_std_gray * static_cast<float>(kPatchSize * kPatchSize);
  const float det = hxx * hyy - hxy * hxy;
  // The smaller eigenvalue of H relative to the larger: an edge (aperture problem) is rejected.
  const float tr = hxx + hyy;
  if (!(ss > min_ss) || !(det > 1e-3F * tr * tr)) {
    return false;
  }
  const float disc = std::sqrt(std::max(0.0F, tr * tr - 4.0F * det));
  out.isotropy = (tr - disc) / (tr + disc);
  out.h_inv_xx = hyy / det;
  out.h_inv_xy = -hxy / det;
  out.h_inv_yy = hxx / det;
  out.valid = true;
  return true;
}

PatchStore::PatchStore()
    : patches_(std::make_unique<std::array<LandmarkPatch, hal::kMaxLandmarks>>()) {}
PatchStore::~PatchStore() = default;

bool PatchStore::capture(int slot, const hal::GrayImageView& image, double u_px, double v_px,
                         double depth_m) {
  if (slot < 0 || slot >= hal::kMaxLandmarks) {
    return false;
  }
  return capture_patch(image, u_px, v_px, depth_m, (*patches_)[static_cast<std::size_t>(slot)]);
}

void PatchStore::clear(int slot) {
  if (slot >= 0 && slot < hal::kMaxLandmarks) {
    (*patches_)[static_cast<std::size_t>(slot)].valid = false;
  }
}

void PatchStore::set_anchor(int slot, const Eigen::Vector3d& camera_position) {
  if (slot >= 0 && slot < hal::kMaxLandmarks && camera_position.allFinite()) {
    LandmarkPatch& p = (*patches_)[static_cast<std::size_t>(slot)];
    p.anchor = {camera_position.x(), camera_position.y(), camera_position.z()};
    p.has_anchor = p.valid;
  }
}

const LandmarkPatch* PatchStore::get(int slot) const {
  if (slot < 0 || slot >= hal::kMaxLandmarks) {
    return nullptr;
  }
  const LandmarkPatch& p = (*patches_)[static_cast<std::size_t>(slot)];
  return p.valid ? &p : nullptr;
}

}  // namespace cleanslam::slam_core::frontend
