#pragma once

#include <cstdint>

#include "cleanslam/hal/image.hpp"
#include "cleanslam/hal/time.hpp"

namespace cleanslam::hal {

// A pixel observation from an external front end (features.csv): distorted pixel coordinates,
// origin at the centre of the top-left pixel, with the tracker's association id.
struct FeatureObservation {
  std::int64_t track_id = 0;
  double u_px = 0.0;
  double v_px = 0.0;
};

// One camera frame. It carries an image, or pixel observations from another front end, or both.
// Both views are non-owning: valid until the source's next call.
struct CameraFrame {
  TimeNs t_ns = 0;
  std::uint32_t seq = 0;
  GrayImageView image;
  const FeatureObservation* features = nullptr;
  int feature_count = 0;

  [[nodiscard]] bool has_image() const { return !image.empty(); }
  [[nodiscard]] bool has_features() const { return features != nullptr && feature_count > 0; }
};

}  // namespace cleanslam::hal
