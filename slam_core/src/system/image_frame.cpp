// SlamSystem's image frames: the front end's records.
#include "cleanslam/slam_core/slam_system.hpp"

namespace cleanslam::slam_core {

namespace lf = hal::log;

// One record per searched landmark (track id: its slot) and per new landmark.
void SlamSystem::collect_image_records() {
  const frontend::FrameReport& report = pipeline_->report();
  for (int i = 0; i < pipeline_->track_count(); ++i) {
    const frontend::TrackRecord& t = pipeline_->tracks()[i];
    lf::UpdateStatus st = lf::UpdateStatus::kRejected;  // not found by the tracker
    if (t.result.found) {
      st = !t.inlier        ? lf::UpdateStatus::kGated
           : report.updated ? lf::UpdateStatus::kUpdated
                            : lf::UpdateStatus::kSkipped;
    }
    record(hal::FeatureObservation{t.slot, t.result.u_px, t.result.v_px}, st, t.slot);
  }
  for (int i = 0; i < pipeline_->new_landmark_count(); ++i) {
    const frontend::PixelObservation& o = pipeline_->new_landmark(i);
    record(hal::FeatureObservation{o.slot, o.u_px, o.v_px}, lf::UpdateStatus::kInitialized, o.slot);
  }
}

}  // namespace cleanslam::slam_core
