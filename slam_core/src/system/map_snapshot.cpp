#include "cleanslam/slam_core/map_snapshot.hpp"

#include <algorithm>

namespace cleanslam::slam_core {

namespace mf = hal::map_file;

static_assert(mf::kMapPatchSide == frontend::kStoredPatchSize);
static_assert(mf::kMaxMapLandmarks >= hal::kMaxLandmarks);

void snapshot_map(const SlamSystem& system, hal::TimeNs t_ns, mf::MapSnapshot& out) {
  const Ekf& ekf = system.ekf();
  out.saved_at_ns = t_ns;
  out.dock = mf::DockPose{};
  out.count = 0;
  for (int s = 0; s < hal::kMaxLandmarks; ++s) {
    if (!ekf.slot_used(s)) {
      continue;
    }
    mf::MapLandmark& l = out.landmarks[static_cast<std::size_t>(out.count++)];
    const std::int64_t track = system.map().owner(s);
    l.id = track >= 0 ? track : s;
    l.flags = 0;
    const Eigen::Vector3d p = ekf.landmark(s);
    const Eigen::Matrix3d c = ekf.landmark_covariance(s);
    l.position_m = {p.x(), p.y(), p.z()};
    l.covariance = {c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2)};
    l.first_depth_m = 0.0;
    l.anchor_m = {};
    l.patch.fill(0.0F);
    const frontend::LandmarkPatch* patch = system.pipeline().patches().get(s);
    if (patch != nullptr && patch->valid) {
      l.flags |= mf::kHasPatch;
      l.first_depth_m = patch->first_depth_m;
      std::copy(patch->pixels.begin(), patch->pixels.end(), l.patch.begin());
      if (patch->has_anchor) {
        l.flags |= mf::kHasAnchor;
        l.anchor_m = patch->anchor;
      }
    }
  }
}

}  // namespace cleanslam::slam_core
