#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "cleanslam/hal/frame.hpp"
#include "cleanslam/hal/pose.hpp"
#include "cleanslam/hal/samples.hpp"
#include "cleanslam/hal/time.hpp"

// The firmware's binary log: everything that crossed the hal boundary, so that a replay through
// the same loop reproduces the outputs bit for bit. Shared by the recorder and the log reader.
//
// File   = FileHeader, then records, append-only.
// Record = RecordHeader (16 bytes) + payload (length bytes). All integers little-endian, doubles
//          as their IEEE-754 bits. The CRC-32 (IEEE 802.3) covers length, type, flags and the
//          payload, so a record cut short by a power loss or damaged on disk is detected and the
//          reader resynchronizes on the next sync word.
namespace cleanslam::hal::log {

inline constexpr std::array<char, 8> kFileMagic{'C', 'S', 'L', 'A', 'M', 'L', 'O', 'G'};
inline constexpr std::uint32_t kFormatVersion = 1;
// magic[8], version u32, file index u32: 0 for the file a run began in, k after k rotations.
inline constexpr std::size_t kFileHeaderSize = 16;

inline constexpr std::uint32_t kRecordSync = 0x52534C43U;  // "CLSR" on disk
inline constexpr std::size_t kRecordHeaderSize =
    16;  // sync u32, length u32, type u16, flags u16, crc u32
inline constexpr std::uint32_t kMaxPayload = 1U << 20;

enum class RecordType : std::uint16_t {
  kConfig = 1,   // u64 FNV-1a hash of the text, then the configuration's YAML text
  kClock = 2,    // i64: the loop's clock when an iteration began (its ingestions follow)
  kGyro = 3,     // GyroSample
  kEncoder = 4,  // EncoderSample
  kFrame = 5,    // CameraFrame: header, features, packed image rows
  kLift = 6,     // i64 t_ns, u8 lifted
  kPose = 16,    // PoseEstimate published by the loop
  kUpdate = 17,  // UpdateRecord: one per observation of a visual update (diagnostics)
  // 18 is not used again: earlier versions wrote odometry fusion records with it.
};

[[nodiscard]] constexpr const char* to_string(RecordType t) {
  switch (t) {
    case RecordType::kConfig:
      return "config";
    case RecordType::kClock:
      return "clock";
    case RecordType::kGyro:
      return "gyro";
    case RecordType::kEncoder:
      return "encoder";
    case RecordType::kFrame:
      return "frame";
    case RecordType::kLift:
      return "lift";
    case RecordType::kPose:
      return "pose";
    case RecordType::kUpdate:
      return "update";
  }
  return "unknown";
}

[[nodiscard]] constexpr bool is_input(RecordType t) {
  return t == RecordType::kGyro || t == RecordType::kEncoder || t == RecordType::kFrame ||
         t == RecordType::kLift;
}
[[nodiscard]] constexpr bool is_output(RecordType t) {
  return t == RecordType::kPose || t == RecordType::kUpdate;
}

// Status of one observation in a visual update (the per-update diagnostics record).
enum class UpdateStatus : std::uint8_t {
  kUpdated = 0,       // fused
  kInitialized = 1,   // new landmark, undelayed initialization (eq. 39-45)
  kGated = 2,         // rejected by the innovation gate / JCBB
  kRejected = 3,      // any other reason: non-finite, outside the image, no positive-definite
                      // covariance, map capacity
  kSkipped = 4,       // no update: too few inliers or standing still
  kNoSlot = 5,        // map full, not initialized
  kMerged = 6,        // a landmark mapped again merged into its earlier entry (slot: that entry)
  kMergeGated = 7,    // the same refused by the merge: the earlier entry was deleted
  kDepthBound = 8,    // the update would have moved the landmark behind the camera or past the
                      // workspace (filter.min_depth_m, max_depth_m)
  kBehindCamera = 9,  // the landmark's estimate is behind the camera: no prediction
};
inline constexpr int kUpdateStatusCount = 10;

struct UpdateRecord {
  TimeNs t_ns = 0;
  std::int64_t track_id = -1;
  std::int32_t slot = -1;
  UpdateStatus status = UpdateStatus::kSkipped;
  double u_px = 0.0;
  double v_px = 0.0;
  double innovation_u = 0.0;
  double innovation_v = 0.0;
  double mahalanobis2 = 0.0;  // kMerged, kMergeGated: the merge's test ratio (3 dof)
};

// CRC-32, reflected polynomial 0xEDB88320, initial value and final xor 0xFFFFFFFF.
struct Crc32Table {
  std::array<std::uint32_t, 256> v{};
  constexpr Crc32Table() {
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) {
        c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
      }
      v[i] = c;
    }
  }
};
inline constexpr Crc32Table kCrc32Table{};

// Running CRC: start with crc32_update(0, ...); feed the previous result to continue.
[[nodiscard]] constexpr std::uint32_t crc32_update(std::uint32_t crc, const std::uint8_t* data,
                                                   std::size_t n) {
  std::uint32_t c = ~crc;
  for (std::size_t i = 0; i < n; ++i) {
    c = kCrc32Table.v[(c ^ data[i]) & 0xFFU] ^ (c >> 8);
  }
  return ~c;
}

[[nodiscard]] constexpr std::uint64_t fnv1a64(const char* data, std::size_t n) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<std::uint8_t>(data[i]);
    h *= 0x100000001b3ULL;
  }
  return h;
}

// Little-endian writer into caller-owned memory; `ok()` turns false on overflow.
class ByteWriter {
 public:
  ByteWriter(std::uint8_t* data, std::size_t capacity) : data_(data), capacity_(capacity) {}
  void u8(std::uint8_t v) { put(v, 1); }
  void u16(std::uint16_t v) { put(v, 2); }
  void u32(std::uint32_t v) { put(v, 4); }
  void u64(std::uint64_t v) { put(v, 8); }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void i64(std::int64_t v) { u64(static_cast<std::uint64_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void bytes(const void* p, std::size_t n) {
    if (!reserve(n)) {
      return;
    }
    if (n > 0) {
      std::memcpy(data_ + size_, p, n);
    }
    size_ += n;
  }
  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] bool ok() const { return ok_; }
  [[nodiscard]] std::uint8_t* data() const { return data_; }

 private:
  bool reserve(std::size_t n) {
    if (!ok_ || capacity_ - size_ < n) {
      ok_ = false;
      return false;
    }
    return true;
  }
  void put(std::uint64_t v, std::size_t n) {
    if (!reserve(n)) {
      return;
    }
    for (std::size_t i = 0; i < n; ++i) {
      data_[size_ + i] = static_cast<std::uint8_t>(v >> (8 * i));
    }
    size_ += n;
  }
  std::uint8_t* data_;
  std::size_t capacity_;
  std::size_t size_ = 0;
  bool ok_ = true;
};

// Little-endian reader over a byte range; `ok()` turns false on a short read.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t u8() { return static_cast<std::uint8_t>(get(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(get(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(get(4)); }
  std::uint64_t u64() { return get(8); }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  std::int64_t i64() { return static_cast<std::int64_t>(u64()); }
  double f64() { return std::bit_cast<double>(u64()); }
  // Pointer to the next n bytes (and skips them), or nullptr on a short read.
  const std::uint8_t* take(std::size_t n) {
    if (!ok_ || size_ - pos_ < n) {
      ok_ = false;
      return nullptr;
    }
    const std::uint8_t* p = data_ + pos_;
    pos_ += n;
    return p;
  }
  [[nodiscard]] std::size_t remaining() const { return size_ - pos_; }
  [[nodiscard]] bool ok() const { return ok_; }

 private:
  std::uint64_t get(std::size_t n) {
    const std::uint8_t* p = take(n);
    if (p == nullptr) {
      return 0;
    }
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < n; ++i) {
      v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
    }
    return v;
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

inline void write_file_header(ByteWriter& w, std::uint32_t file_index = 0) {
  w.bytes(kFileMagic.data(), kFileMagic.size());
  w.u32(kFormatVersion);
  w.u32(file_index);
}

// Fills the 16-byte header in front of a payload of `length` bytes already at header + 16.
inline void seal_record(std::uint8_t* header, RecordType type, std::uint32_t length) {
  ByteWriter w(header, kRecordHeaderSize);
  w.u32(kRecordSync);
  w.u32(length);
  w.u16(static_cast<std::uint16_t>(type));
  w.u16(0);
  std::uint32_t crc = crc32_update(0, header + 4, 8);
  crc = crc32_update(crc, header + kRecordHeaderSize, length);
  w.u32(crc);
}

struct RecordHeader {
  std::uint32_t sync = 0;
  std::uint32_t length = 0;
  RecordType type = RecordType::kClock;
  std::uint16_t flags = 0;
  std::uint32_t crc = 0;
};

inline RecordHeader read_record_header(const std::uint8_t* p) {
  ByteReader r(p, kRecordHeaderSize);
  RecordHeader h;
  h.sync = r.u32();
  h.length = r.u32();
  h.type = static_cast<RecordType>(r.u16());
  h.flags = r.u16();
  h.crc = r.u32();
  return h;
}

// CRC of a record whose header and `h.length` payload bytes start at p.
[[nodiscard]] inline std::uint32_t record_crc(const std::uint8_t* p, const RecordHeader& h) {
  const std::uint32_t crc = crc32_update(0, p + 4, 8);
  return crc32_update(crc, p + kRecordHeaderSize, h.length);
}

// --- payloads -------------------------------------------------------------------------------

inline void encode(ByteWriter& w, const GyroSample& s) {
  w.i64(s.t_ns);
  w.f64(s.wz_rad_s);
  w.f64(s.wx_rad_s);
  w.f64(s.wy_rad_s);
  w.u8(s.has_xy ? 1 : 0);
  w.u32(s.seq);
}
inline bool decode(ByteReader& r, GyroSample& s) {
  s.t_ns = r.i64();
  s.wz_rad_s = r.f64();
  s.wx_rad_s = r.f64();
  s.wy_rad_s = r.f64();
  s.has_xy = r.u8() != 0;
  s.seq = r.u32();
  return r.ok();
}

inline void encode(ByteWriter& w, const EncoderSample& s) {
  w.i64(s.t_ns);
  w.i32(s.left_ticks);
  w.i32(s.right_ticks);
  w.u32(s.seq);
}
inline bool decode(ByteReader& r, EncoderSample& s) {
  s.t_ns = r.i64();
  s.left_ticks = r.i32();
  s.right_ticks = r.i32();
  s.seq = r.u32();
  return r.ok();
}

inline constexpr std::size_t kGyroPayload = 37;
inline constexpr std::size_t kEncoderPayload = 20;
inline constexpr std::size_t kLiftPayload = 9;
inline constexpr std::size_t kPosePayload = 360;
inline constexpr std::size_t kUpdatePayload = 61;
inline constexpr std::size_t kFeatureBytes = 24;
inline constexpr std::size_t kFrameHeaderBytes = 20;

// Frame payload: t_ns i64, seq u32, width u16, height u16 (0 without image), feature_count u16,
// flags u16, then feature_count x (track_id i64, u f64, v f64), then width*height image bytes.
[[nodiscard]] inline std::size_t frame_payload_size(const CameraFrame& f) {
  const std::size_t image = f.has_image() ? static_cast<std::size_t>(f.image.width) *
                                                static_cast<std::size_t>(f.image.height)
                                          : 0;
  const std::size_t features = f.has_features() ? static_cast<std::size_t>(f.feature_count) : 0;
  return kFrameHeaderBytes + features * kFeatureBytes + image;
}
inline void encode(ByteWriter& w, const CameraFrame& f) {
  const bool image = f.has_image();
  const int n = f.has_features() ? f.feature_count : 0;
  w.i64(f.t_ns);
  w.u32(f.seq);
  w.u16(static_cast<std::uint16_t>(image ? f.image.width : 0));
  w.u16(static_cast<std::uint16_t>(image ? f.image.height : 0));
  w.u16(static_cast<std::uint16_t>(n));
  w.u16(0);
  for (int i = 0; i < n; ++i) {
    w.i64(f.features[i].track_id);
    w.f64(f.features[i].u_px);
    w.f64(f.features[i].v_px);
  }
  if (image) {
    for (int y = 0; y < f.image.height; ++y) {
      w.bytes(f.image.row(y), static_cast<std::size_t>(f.image.width));
    }
  }
}
// Decodes into `f`; features are written to `features` (capacity `max_features`, extra ones are
// an error) and the image view points into the payload.
inline bool decode(ByteReader& r, CameraFrame& f, FeatureObservation* features, int max_features) {
  f.t_ns = r.i64();
  f.seq = r.u32();
  const int width = r.u16();
  const int height = r.u16();
  const int n = r.u16();
  (void)r.u16();
  if (!r.ok() || n > max_features) {
    return false;
  }
  for (int i = 0; i < n; ++i) {
    features[i].track_id = r.i64();
    features[i].u_px = r.f64();
    features[i].v_px = r.f64();
  }
  f.features = n > 0 ? features : nullptr;
  f.feature_count = n;
  f.image = GrayImageView{};
  if (width > 0 && height > 0) {
    const std::uint8_t* pixels =
        r.take(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    if (pixels == nullptr) {
      return false;
    }
    f.image = GrayImageView{pixels, width, height, width};
  }
  return r.ok();
}

inline void encode_lift(ByteWriter& w, TimeNs t_ns, bool lifted) {
  w.i64(t_ns);
  w.u8(lifted ? 1 : 0);
}

inline void encode(ByteWriter& w, const PoseEstimate& p) {
  w.i64(p.t_ns);
  for (double v : p.position_m) {
    w.f64(v);
  }
  for (double v : p.orientation_wxyz) {
    w.f64(v);
  }
  for (double v : p.covariance) {
    w.f64(v);
  }
  w.u32(p.health);
  w.u16(p.landmarks_in_map);
  w.u16(p.landmarks_in_view);
}
inline bool decode(ByteReader& r, PoseEstimate& p) {
  p.t_ns = r.i64();
  for (double& v : p.position_m) {
    v = r.f64();
  }
  for (double& v : p.orientation_wxyz) {
    v = r.f64();
  }
  for (double& v : p.covariance) {
    v = r.f64();
  }
  p.health = r.u32();
  p.landmarks_in_map = r.u16();
  p.landmarks_in_view = r.u16();
  return r.ok();
}

inline void encode(ByteWriter& w, const UpdateRecord& u) {
  w.i64(u.t_ns);
  w.i64(u.track_id);
  w.i32(u.slot);
  w.u8(static_cast<std::uint8_t>(u.status));
  w.f64(u.u_px);
  w.f64(u.v_px);
  w.f64(u.innovation_u);
  w.f64(u.innovation_v);
  w.f64(u.mahalanobis2);
}
inline bool decode(ByteReader& r, UpdateRecord& u) {
  u.t_ns = r.i64();
  u.track_id = r.i64();
  u.slot = r.i32();
  u.status = static_cast<UpdateStatus>(r.u8());
  u.u_px = r.f64();
  u.v_px = r.f64();
  u.innovation_u = r.f64();
  u.innovation_v = r.f64();
  u.mahalanobis2 = r.f64();
  return r.ok();
}

}  // namespace cleanslam::hal::log
