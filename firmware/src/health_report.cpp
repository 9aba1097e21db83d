#include "cleanslam/firmware/health_report.hpp"

#include <utility>

#include "cleanslam/firmware/summary_words.hpp"
#include "cleanslam/hal/pose.hpp"
#include "cleanslam/hal/time.hpp"

namespace cleanslam::firmware {

namespace {

constexpr std::array<std::pair<std::uint32_t, const char*>, 5> kNames{{
    {hal::kGyroSilent, "gyro silent (heading from encoders)"},
    {hal::kEncodersSilent, "encoders silent (distance from a motion model)"},
    {hal::kCameraSilent, "camera silent (dead reckoning only)"},
    {hal::kLifted, "lifted"},
    {hal::kPoseLost, "pose lost"},
}};

constexpr std::array<std::uint32_t, HealthReport::kSourceCount> kSilentBits{
    hal::kGyroSilent, hal::kEncodersSilent, hal::kCameraSilent};

}  // namespace

const char* HealthReport::source_name(Source s) {
  switch (s) {
    case kGyro:
      return "gyro";
    case kEncoders:
      return "encoders";
    case kCamera:
      return "camera";
    case kSourceCount:
      break;
  }
  return "?";
}

void HealthReport::health_changed(std::int64_t t_ns, std::uint32_t before, std::uint32_t after) {
  for (const auto& [bit, name] : kNames) {
    if ((after & bit) != 0 && (before & bit) == 0) {
      std::fprintf(out_, "%s: t=%.3f s: %s\n", program_, hal::to_seconds(t_ns), name);
    } else if ((after & bit) == 0 && (before & bit) != 0) {
      std::fprintf(out_, "%s: t=%.3f s: recovered: %s\n", program_, hal::to_seconds(t_ns), name);
    }
  }
  for (std::size_t i = 0; i < kSilentBits.size(); ++i) {
    Silence& s = silences_[i];
    const std::uint32_t bit = kSilentBits[i];
    if ((after & bit) != 0 && (before & bit) == 0) {
      ++s.episodes;
      s.since_ns = t_ns;
      if (s.first_ns < 0) {
        s.first_ns = t_ns;
      }
    } else if ((after & bit) == 0 && (before & bit) != 0 && s.since_ns >= 0) {
      s.total_ns += t_ns - s.since_ns;
      s.since_ns = -1;
    }
  }
}

void HealthReport::first_reject(std::int64_t t_ns, Reject r) {
  std::fprintf(out_, "%s: t=%.3f s: input refused (%s): %s; later ones are counted\n", program_,
               hal::to_seconds(t_ns), to_string(r), explain(r));
}

void HealthReport::finish(std::int64_t end_ns) {
  for (Silence& s : silences_) {
    if (s.since_ns >= 0) {
      s.total_ns += end_ns - s.since_ns;
      s.since_ns = -1;
    }
  }
}

}  // namespace cleanslam::firmware
