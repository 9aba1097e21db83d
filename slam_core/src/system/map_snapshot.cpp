#include "cleanslam/slam_core/map_snapshot.hpp"

#include <algorithm>
#include <cmath>

namespace cleanslam::slam_core {

namespace mf = hal::map_file;

static_assert(mf::kMapPatchSide == frontend::kStoredPatchSize);
static_assert(mf::kMaxMapLandmarks >= hal::kMaxLandmarks);

namespace {

bool within(double v, double lo, double hi) {
  return std::isfinite(v) && v >= lo && v <= hi;
}

// A landmark the map file can hold (hal/map_file.hpp's bounds); one that diverged is left out, so
// that it cannot get the whole map refused at the next start.
bool plausible(const Eigen::Vector3d& p, const std::array<double, 6>& c) {
  for (int i = 0; i < 3; ++i) {
    if (!within(p(i), -mf::kMaxAbsCoordinateM, mf::kMaxAbsCoordinateM)) {
      return false;
    }
  }
  for (const double v : c) {
    if (!std::isfinite(v)) {
      return false;
    }
  }
  return c[0] <= mf::kMaxVarianceM2 && c[3] <= mf::kMaxVarianceM2 && c[5] <= mf::kMaxVarianceM2 &&
         c[0] >= 0.0 && c[3] >= 0.0 && c[5] >= 0.0 && mf::covariance_ok(c);
}

bool plausible_anchor(const std::array<double, 3>& a) {
  return std::all_of(a.begin(), a.end(), [](double v) {
    return within(v, -mf::kMaxAbsCoordinateM, mf::kMaxAbsCoordinateM);
  });
}

}  // namespace

void snapshot_map(const SlamSystem& system, hal::TimeNs t_ns, mf::MapSnapshot& out) {
  const Ekf& ekf = system.ekf();
  out.saved_at_ns = t_ns;
  out.dock = mf::DockPose{};
  out.count = 0;
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    if (!ekf.slot_used(s)) {
      continue;
    }
    const Eigen::Vector3d p = ekf.landmark(s);
    const Eigen::Matrix3d c = ekf.landmark_covariance(s);
    const std::array<double, 6> upper{c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2)};
    if (!plausible(p, upper)) {
      continue;
    }
    const std::int64_t track = system.map().owner(s);
    const std::int64_t id = track >= 0 ? track : s;
    const auto end = out.landmarks.begin() + out.count;
    if (std::any_of(out.landmarks.begin(), end,
                    [id](const mf::MapLandmark& other) { return other.id == id; })) {
      continue;  // a slot's number that is also another landmark's track id: ids stay distinct
    }
    mf::MapLandmark& l = out.landmarks[static_cast<std::size_t>(out.count++)];
    l.id = id;
    l.flags = 0;
    l.position_m = {p.x(), p.y(), p.z()};
    l.covariance = upper;
    l.first_depth_m = 0.0;
    l.anchor_m = {};
    l.patch.fill(0.0F);
    const frontend::LandmarkPatch* patch = system.pipeline().patches().get(s);
    if (patch != nullptr && patch->valid &&
        within(patch->first_depth_m, 0.0, mf::kMaxAbsCoordinateM) && patch->first_depth_m > 0.0) {
      l.flags |= mf::kHasPatch;
      l.first_depth_m = patch->first_depth_m;
      // Bilinear samples of 8-bit pixels, held to the grey range against the weights' rounding.
      std::transform(patch->pixels.begin(), patch->pixels.end(), l.patch.begin(),
                     [](float v) { return std::clamp(v, 0.0F, mf::kMaxGrey); });
      if (patch->has_anchor && plausible_anchor(patch->anchor)) {
        l.flags |= mf::kHasAnchor;
        l.anchor_m = patch->anchor;
      }
    }
  }
}

}  // namespace cleanslam::slam_core
