#include "cleanslam/firmware/run_report.hpp"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "cleanslam/firmware/sinks.hpp"
#include "cleanslam/firmware/summary_words.hpp"

namespace cleanslam::firmware {

namespace {

void print_camera_offset(const CameraOffsetEstimate::Result& c, std::FILE* out) {
  if (!c.measurable) {
    std::fprintf(out,
                 "cleanslam: camera time offset: not measurable (%llu points seen in consecutive "
                 "frames; it needs turning with points in view)\n",
                 static_cast<unsigned long long>(c.pairs));
    return;
  }
  std::fprintf(
      out,
      "cleanslam: camera time offset: the data suggest %+.3f s (+- %.4f s from the "
      "scatter, %llu points seen in consecutive frames); camera.time_offset_s is %+.3f s\n",
      c.suggested_s, c.std_s, static_cast<unsigned long long>(c.pairs), c.configured_s);
  const double d = c.suggested_s - c.configured_s;
  if (std::abs(d) > CameraOffsetEstimate::kWarnS && std::abs(d) > 3.0 * c.std_s) {
    std::fprintf(out, "cleanslam: warning: camera.time_offset_s looks off by %+.3f s\n", d);
  }
}
}  // namespace

void print_summary(const Loop& loop, const CameraOffsetEstimate& camera_offset, std::FILE* out) {
  const LoopStats& s = loop.stats();
  std::fprintf(
      out,
      "cleanslam: %llu iterations, %llu gyro, %llu encoder samples, %llu frames in, %llu "
      "processed, %llu predictions, %llu poses, %llu update records\n",
      static_cast<unsigned long long>(s.iterations), static_cast<unsigned long long>(s.gyro),
      static_cast<unsigned long long>(s.encoders), static_cast<unsigned long long>(s.frames_in),
      static_cast<unsigned long long>(s.frames_done),
      static_cast<unsigned long long>(s.predictions), static_cast<unsigned long long>(s.poses),
      static_cast<unsigned long long>(s.update_records));
  std::fputs("cleanslam: update records by status:", out);
  const char* separator = "";
  for (std::size_t i = 0; i < s.records_by_status.size(); ++i) {
    if (s.records_by_status[i] > 0) {
      std::fprintf(out, "%s %s %llu", separator, to_string(static_cast<hal::log::UpdateStatus>(i)),
                   static_cast<unsigned long long>(s.records_by_status[i]));
      separator = ",";
    }
  }
  std::fputs(separator[0] == '\0' ? " none\n" : "\n", out);
  for (std::size_t i = 0; i < s.records_by_status.size(); ++i) {
    if (s.records_by_status[i] > 0) {
      const auto status = static_cast<hal::log::UpdateStatus>(i);
      std::fprintf(out, "cleanslam:   %-14s %llu %s\n", to_string(status),
                   static_cast<unsigned long long>(s.records_by_status[i]), explain(status));
    }
  }
  const MapCounters m = loop.estimator().map_counters();
  std::fprintf(
      out,
      "cleanslam: map: %llu landmarks initialized, %llu replaced, %llu deleted, %llu "
      "merged, %llu merges gated\n",
      static_cast<unsigned long long>(m.initialized), static_cast<unsigned long long>(m.replaced),
      static_cast<unsigned long long>(m.deleted), static_cast<unsigned long long>(m.merged),
      static_cast<unsigned long long>(m.merges_gated));
  const ObservationRejections r = loop.estimator().observation_rejections();
  if (r.count > 0) {
    std::fputs("cleanslam: measurements not fused:", out);
    for (int i = 0; i < r.count; ++i) {
      const ObservationRejection& e = r.by_reason[static_cast<std::size_t>(i)];
      std::fprintf(out, "%s %s %llu", i > 0 ? "," : "", e.reason,
                   static_cast<unsigned long long>(e.count));
    }
    std::fputc('\n', out);
    for (int i = 0; i < r.count; ++i) {
      const ObservationRejection& e = r.by_reason[static_cast<std::size_t>(i)];
      std::fprintf(out, "cleanslam:   %-14s %s\n", e.reason, explain_observation_reason(e.reason));
    }
  }
  WheelYawReport w;
  if (loop.estimator().wheel_yaw(w)) {
    std::fprintf(out,
                 "cleanslam: wheel heading: scale %+.4f (std. dev. %.4f), drift %+.4f rad/m (std. "
                 "dev. %.4f), gyro bias %+.5f rad/s; %llu intervals fused, %llu gated, %llu "
                 "windows learnt, %llu taken back to the gyro\n",
                 w.scale, w.scale_std, w.drift_rad_per_m, w.drift_std, w.gyro_bias_rad_s,
                 static_cast<unsigned long long>(w.intervals_fused),
                 static_cast<unsigned long long>(w.intervals_gated),
                 static_cast<unsigned long long>(w.windows_used),
                 static_cast<unsigned long long>(w.windows_gated));
  }
  print_camera_offset(camera_offset.result(), out);
  for (std::size_t i = 0; i < kRejectCount; ++i) {
    if (s.rejects.n[i] > 0) {
      std::fprintf(out, "cleanslam: rejected %s: %llu %s\n", to_string(static_cast<Reject>(i)),
                   static_cast<unsigned long long>(s.rejects.n[i]),
                   explain(static_cast<Reject>(i)));
    }
  }
}

bool write_landmarks_csv(const Estimator& estimator, const std::string& path, std::string& error) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) {
    error = path + ": cannot create: " + std::strerror(errno);
    return false;
  }
  std::array<LandmarkEstimate, hal::kMaxLandmarks> lm{};
  const int n = estimator.landmarks(lm.data(), static_cast<int>(lm.size()));
  std::fputs("#slot,x,y,z,sxx,sxy,sxz,syy,syz,szz\n", f);
  for (int i = 0; i < n; ++i) {
    const auto& l = lm[static_cast<std::size_t>(i)];
    const auto& c = l.covariance;
    std::fprintf(f, "%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", l.slot, l.position_m[0],
                 l.position_m[1], l.position_m[2], c[0], c[1], c[2], c[4], c[5], c[8]);
  }
  return std::fclose(f) == 0;
}

}  // namespace cleanslam::firmware
