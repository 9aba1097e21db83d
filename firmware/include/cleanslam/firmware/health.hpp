#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace cleanslam::firmware {

// Why an input was not used. Counted, never fatal.
enum class Reject : std::uint8_t {
  kOutOfOrder,       // time stamp not after the previous one of the same sensor
  kTimeJump,         // time stamp too far from the loop's clock, or past the run's span
  kNonFinite,        // NaN or infinity in a sample
  kFrameRate,        // frame closer to the last accepted one than the configured rate allows
  kFrameSuperseded,  // waiting frame replaced by a newer one before processing began
  kBadFrame,         // image larger than the capacity, or no image and no features
  kImageSize,        // image of another size than the calibrated one
  kBadFeature,       // non-finite feature, or more than the capacity
  kCorruptRecord,    // damaged or truncated log record (replay)
  kRecorderDropped,  // the recorder's buffer was full
  kCount
};
inline constexpr std::size_t kRejectCount = static_cast<std::size_t>(Reject::kCount);
const char* to_string(Reject r);

struct RejectCounters {
  std::array<std::uint64_t, kRejectCount> n{};
  void add(Reject r, std::uint64_t k = 1) { n[static_cast<std::size_t>(r)] += k; }
  [[nodiscard]] std::uint64_t operator[](Reject r) const { return n[static_cast<std::size_t>(r)]; }
  [[nodiscard]] std::uint64_t total() const;
};

// Told when health flags (hal::HealthFlag) change.
class HealthObserver {
 public:
  virtual ~HealthObserver() = default;
  virtual void health_changed(std::int64_t t_ns, std::uint32_t before, std::uint32_t after) = 0;
  // The first input refused for reason `r` (later ones are only counted).
  virtual void first_reject(std::int64_t /*t_ns*/, Reject /*r*/) {}
};

}  // namespace cleanslam::firmware
