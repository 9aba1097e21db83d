#include "cleanslam/readers/dataset_source.hpp"

#include <cmath>
#include <limits>

namespace cleanslam::readers {
namespace {
constexpr hal::TimeNs kNever = std::numeric_limits<hal::TimeNs>::max();
}

Result<DatasetSource> DatasetSource::open(const std::string& folder, const Options& options) {
  auto d = load_dataset(folder, options.load);
  if (!d.ok()) return Result<DatasetSource>::failure(d.error());
  DatasetSource src;
  src.dataset_ = std::move(d).value();
  if (options.apply_time_offset) {
    src.frame_offset_ns_ =
        static_cast<hal::TimeNs>(std::llround(src.dataset_.calibration.camera.time_offset_s * 1e9));
  }
  const auto& cam = src.dataset_.camera;
  const auto& feat = src.dataset_.features;
  std::size_t ci = 0;
  std::size_t fi = 0;
  while (ci < cam.size() || fi < feat.size()) {
    const hal::TimeNs tc = ci < cam.size() ? cam[ci].t_ns : kNever;
    const hal::TimeNs tf = fi < feat.size() ? feat[fi].t_ns : kNever;
    FrameIndex f;
    f.t_ns = std::min(tc, tf);
    if (tc == f.t_ns) f.camera_row = static_cast<int>(ci++);
    if (tf == f.t_ns) {
      f.feature_begin = fi;
      while (fi < feat.size() && feat[fi].t_ns == f.t_ns) ++fi;
      const std::size_t n = fi - f.feature_begin;
      if (n > static_cast<std::size_t>(hal::kMaxFeaturesPerFrame)) {
        src.dataset_.warnings.push_back(folder + "/features.csv: frame at t_ns " +
                                        std::to_string(f.t_ns) + " has " + std::to_string(n) +
                                        " features, only the first " +
                                        std::to_string(hal::kMaxFeaturesPerFrame) + " are used");
      }
      f.feature_count =
          static_cast<int>(std::min(n, static_cast<std::size_t>(hal::kMaxFeaturesPerFrame)));
    }
    src.frames_.push_back(f);
  }
  src.frame_features_.reserve(static_cast<std::size_t>(hal::kMaxFeaturesPerFrame));
  return src;
}

hal::TimeNs DatasetSource::next_event_time() const {
  hal::TimeNs t = kNever;
  if (next_gyro_ < dataset_.gyro.size()) t = std::min(t, dataset_.gyro[next_gyro_].t_ns);
  if (next_encoder_ < dataset_.encoders.size()) {
    t = std::min(t, dataset_.encoders[next_encoder_].t_ns);
  }
  if (next_lift_ < dataset_.lift.size()) t = std::min(t, dataset_.lift[next_lift_].t_ns);
  if (next_frame_ < frames_.size()) t = std::min(t, frames_[next_frame_].t_ns + frame_offset_ns_);
  return t == kNever ? -1 : t;
}

bool DatasetSource::exhausted() const {
  return next_gyro_ >= dataset_.gyro.size() && next_encoder_ >= dataset_.encoders.size() &&
         next_frame_ >= frames_.size() && next_lift_ >= dataset_.lift.size();
}

bool DatasetSource::read(hal::SensorEvent& out) {
  if (exhausted()) return false;
  const hal::TimeNs t = next_event_time();
  out = hal::SensorEvent{};
  if (next_gyro_ < dataset_.gyro.size() && dataset_.gyro[next_gyro_].t_ns == t) {
    out.kind = hal::SensorEvent::Kind::kGyro;
    out.gyro = dataset_.gyro[next_gyro_++];
    return true;
  }
  if (next_encoder_ < dataset_.encoders.size() && dataset_.encoders[next_encoder_].t_ns == t) {
    out.kind = hal::SensorEvent::Kind::kEncoder;
    out.encoder = dataset_.encoders[next_encoder_++];
    return true;
  }
  if (next_lift_ < dataset_.lift.size() && dataset_.lift[next_lift_].t_ns == t) {
    out.kind = hal::SensorEvent::Kind::kLift;
    out.lifted = dataset_.lift[next_lift_++].lifted;
    return true;
  }
  const FrameIndex& f = frames_[next_frame_];
  out.kind = hal::SensorEvent::Kind::kFrame;
  out.frame.t_ns = t;
  out.frame.seq = static_cast<std::uint32_t>(next_frame_);
  if (f.camera_row >= 0) {
    const CameraIndexRow& row = dataset_.camera[static_cast<std::size_t>(f.camera_row)];
    Status s = read_gray_image(dataset_.image_path(row), image_);
    if (s && (image_.width != dataset_.calibration.camera.width ||
              image_.height != dataset_.calibration.camera.height)) {
      s = Status::failure(dataset_.image_path(row) + ": wrong image size");
    }
    if (s) {
      out.frame.image = image_.view();
    } else {
      ++image_errors_;
      last_error_ = s.error();
    }
  }
  frame_features_.clear();
  for (int i = 0; i < f.feature_count; ++i) {
    frame_features_.push_back(
        dataset_.features[f.feature_begin + static_cast<std::size_t>(i)].observation);
  }
  if (!frame_features_.empty()) {
    out.frame.features = frame_features_.data();
    out.frame.feature_count = f.feature_count;
  }
  ++next_frame_;
  return true;
}

}  // namespace cleanslam::readers
