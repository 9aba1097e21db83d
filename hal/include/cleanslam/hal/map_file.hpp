#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/log_format.hpp"
#include "cleanslam/hal/time.hpp"

// The map kept across cleaning runs: what a run leaves for the next one to start from. Written by
// the firmware at a clean stop and every few minutes (atomically: a temporary file, fsync,
// rename), read at start-up.
//
// File = header (64 bytes), `count` landmark records, CRC-32 of everything before it (u32).
// Header = magic[8], version u32, header size u32, record size u32, count u32, flags u32,
//          saved_at_ns i64, dock pose (x m, y m, yaw rad) f64 x 3, reserved u32.
// Record = id i64, flags u32 (kHasPatch, kHasAnchor), reserved u32, position f64 x 3,
//          covariance f64 x 6 (xx xy xz yy yz zz), first depth f64, anchor f64 x 3,
//          patch f32 x kMapPatchSide^2.
// Little-endian, doubles and floats as their IEEE-754 bits, like the log (log_format.hpp).
namespace cleanslam::hal::map_file {

inline constexpr std::array<char, 8> kMagic{'C', 'S', 'L', 'A', 'M', 'M', 'A', 'P'};
inline constexpr std::uint32_t kVersion = 1;
inline constexpr std::size_t kHeaderSize = 64;
// The appearance the front end finds a landmark by: its stored first-sighting window.
inline constexpr int kMapPatchSide = 31;
inline constexpr std::size_t kPatchPixels =
    static_cast<std::size_t>(kMapPatchSide) * static_cast<std::size_t>(kMapPatchSide);
inline constexpr std::size_t kRecordSize = 8 + 4 + 4 + 8 * 3 + 8 * 6 + 8 + 8 * 3 + 4 * kPatchPixels;
// What a file may hold; a count beyond it is refused before anything is read.
inline constexpr int kMaxMapLandmarks = kMaxLandmarks;
inline constexpr std::size_t kMaxFileSize =
    kHeaderSize + kRecordSize * static_cast<std::size_t>(kMaxMapLandmarks) + 4;

enum RecordFlag : std::uint32_t {
  kHasPatch = 1U << 0,
  kHasAnchor = 1U << 1,
};

struct MapLandmark {
  std::int64_t id = 0;  // the track id of feature frames, the slot of image frames
  std::uint32_t flags = 0;
  std::array<double, 3> position_m{};
  std::array<double, 6> covariance{};  // xx xy xz yy yz zz, m^2
  double first_depth_m = 0.0;
  std::array<double, 3> anchor_m{};  // the camera at the first sighting
  std::array<float, kPatchPixels> patch{};

  bool operator==(const MapLandmark&) const = default;
};

// The dock: where the run that saved the map began, in the map's frame.
struct DockPose {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
};

struct MapSnapshot {
  TimeNs saved_at_ns = 0;
  DockPose dock{};
  int count = 0;
  std::array<MapLandmark, kMaxMapLandmarks> landmarks{};
};

[[nodiscard]] constexpr std::size_t file_size(int count) {
  return kHeaderSize + kRecordSize * static_cast<std::size_t>(count) + 4;
}

// Writes the file's bytes into `out` (at least file_size(m.count) long); returns their number, or 0
// when the snapshot does not fit.
inline std::size_t encode(const MapSnapshot& m, std::uint8_t* out, std::size_t capacity) {
  if (m.count < 0 || m.count > kMaxMapLandmarks || capacity < file_size(m.count)) {
    return 0;
  }
  log::ByteWriter w(out, capacity);
  w.bytes(kMagic.data(), kMagic.size());
  w.u32(kVersion);
  w.u32(static_cast<std::uint32_t>(kHeaderSize));
  w.u32(static_cast<std::uint32_t>(kRecordSize));
  w.u32(static_cast<std::uint32_t>(m.count));
  w.u32(0);
  w.i64(m.saved_at_ns);
  w.f64(m.dock.x_m);
  w.f64(m.dock.y_m);
  w.f64(m.dock.yaw_rad);
  w.u32(0);
  for (int i = 0; i < m.count; ++i) {
    const MapLandmark& l = m.landmarks[static_cast<std::size_t>(i)];
    w.i64(l.id);
    w.u32(l.flags);
    w.u32(0);
    for (const double v : l.position_m) {
      w.f64(v);
    }
    for (const double v : l.covariance) {
      w.f64(v);
    }
    w.f64(l.first_depth_m);
    for (const double v : l.anchor_m) {
      w.f64(v);
    }
    for (const float v : l.patch) {
      w.u32(std::bit_cast<std::uint32_t>(v));
    }
  }
  w.u32(log::crc32_update(0, out, w.size()));
  return w.ok() ? w.size() : 0;
}

enum class Refusal {
  kNone,
  kTooShort,      // shorter than a header and its CRC
  kNotAMap,       // another file's magic
  kOtherVersion,  // written by another version of the format
  kLayout,        // header or record size other than this version's
  kTooManyLandmarks,
  kSize,           // the size does not match the count: cut short, or bytes appended
  kCrc,            // damaged
  kNotFinite,      // a position, covariance, dock or patch value is NaN or infinite
  kNotCovariance,  // a covariance that is not symmetric positive semi-definite
};

[[nodiscard]] constexpr const char* to_string(Refusal r) {
  switch (r) {
    case Refusal::kNone:
      return "none";
    case Refusal::kTooShort:
      return "shorter than a map file's header";
    case Refusal::kNotAMap:
      return "not a cleanslam map file (magic)";
    case Refusal::kOtherVersion:
      return "written by another version of the map format";
    case Refusal::kLayout:
      return "header or record size not this version's";
    case Refusal::kTooManyLandmarks:
      return "more landmarks than the firmware holds";
    case Refusal::kSize:
      return "size does not match its landmark count (cut short or appended to)";
    case Refusal::kCrc:
      return "CRC mismatch (damaged)";
    case Refusal::kNotFinite:
      return "a value that is not finite";
    case Refusal::kNotCovariance:
      return "a landmark covariance that is not positive semi-definite";
  }
  return "unknown";
}

struct Decoded {
  Refusal refusal = Refusal::kNone;
  std::size_t offset = 0;  // where the refused value begins
  std::uint32_t version = 0;
  std::uint32_t count = 0;
};

// A 3x3 covariance stored as its upper triangle is positive semi-definite: every principal minor
// is non-negative (the leading ones alone prove only definiteness), with a tolerance for rounding
// at the diagonal's scale.
[[nodiscard]] inline bool covariance_ok(const std::array<double, 6>& c) {
  const double xx = c[0];
  const double xy = c[1];
  const double xz = c[2];
  const double yy = c[3];
  const double yz = c[4];
  const double zz = c[5];
  const double scale = std::max({std::abs(xx), std::abs(yy), std::abs(zz)});
  const double tol = 1e-9 * scale;
  if (!(xx >= -tol && yy >= -tol && zz >= -tol)) {
    return false;
  }
  const double m_xy = xx * yy - xy * xy;
  const double m_xz = xx * zz - xz * xz;
  const double m_yz = yy * zz - yz * yz;
  const double det = xx * m_yz - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
  return m_xy >= -tol * scale && m_xz >= -tol * scale && m_yz >= -tol * scale &&
         det >= -tol * scale * scale;
}

// Reads a whole file's bytes into `m`; `m` is left with count 0 unless the file is accepted.
inline Decoded decode(const std::uint8_t* data, std::size_t size, MapSnapshot& m) {
  Decoded d;
  m.count = 0;
  const auto refuse = [&d](Refusal r, std::size_t at) {
    d.refusal = r;
    d.offset = at;
    return d;
  };
  if (size < kHeaderSize + 4) {
    return refuse(Refusal::kTooShort, size);
  }
  log::ByteReader r(data, size);
  const std::uint8_t* magic = r.take(kMagic.size());
  for (std::size_t i = 0; i < kMagic.size(); ++i) {
    if (magic[i] != static_cast<std::uint8_t>(kMagic[i])) {
      return refuse(Refusal::kNotAMap, 0);
    }
  }
  d.version = r.u32();
  if (d.version != kVersion) {
    return refuse(Refusal::kOtherVersion, 8);
  }
  const std::uint32_t header_size = r.u32();
  const std::uint32_t record_size = r.u32();
  if (header_size != kHeaderSize || record_size != kRecordSize) {
    return refuse(Refusal::kLayout, header_size != kHeaderSize ? 12 : 16);
  }
  d.count = r.u32();
  if (d.count > static_cast<std::uint32_t>(kMaxMapLandmarks)) {
    return refuse(Refusal::kTooManyLandmarks, 20);
  }
  if (size != file_size(static_cast<int>(d.count))) {
    return refuse(Refusal::kSize, std::min(size, file_size(static_cast<int>(d.count))));
  }
  log::ByteReader tail(data + size - 4, 4);
  if (tail.u32() != log::crc32_update(0, data, size - 4)) {
    return refuse(Refusal::kCrc, size - 4);
  }
  (void)r.u32();  // flags
  const TimeNs saved_at = r.i64();
  DockPose dock;
  dock.x_m = r.f64();
  dock.y_m = r.f64();
  dock.yaw_rad = r.f64();
  (void)r.u32();
  if (!std::isfinite(dock.x_m) || !std::isfinite(dock.y_m) || !std::isfinite(dock.yaw_rad)) {
    return refuse(Refusal::kNotFinite, 36);
  }
  for (std::uint32_t i = 0; i < d.count; ++i) {
    const std::size_t at = kHeaderSize + kRecordSize * i;
    MapLandmark& l = m.landmarks[i];
    l.id = r.i64();
    l.flags = r.u32();
    (void)r.u32();
    bool finite = true;
    for (double& v : l.position_m) {
      v = r.f64();
      finite = finite && std::isfinite(v);
    }
    for (double& v : l.covariance) {
      v = r.f64();
      finite = finite && std::isfinite(v);
    }
    l.first_depth_m = r.f64();
    for (double& v : l.anchor_m) {
      v = r.f64();
    }
    for (float& v : l.patch) {
      v = std::bit_cast<float>(r.u32());
      finite = finite && std::isfinite(v);
    }
    if ((l.flags & kHasPatch) != 0) {
      finite = finite && std::isfinite(l.first_depth_m);
    } else {
      l.first_depth_m = 0.0;
    }
    if ((l.flags & kHasAnchor) != 0) {
      for (const double v : l.anchor_m) {
        finite = finite && std::isfinite(v);
      }
    } else {
      l.anchor_m = {};
    }
    if (!finite) {
      return refuse(Refusal::kNotFinite, at);
    }
    if (!covariance_ok(l.covariance)) {
      return refuse(Refusal::kNotCovariance, at + 40);
    }
  }
  m.saved_at_ns = saved_at;
  m.dock = dock;
  m.count = static_cast<int>(d.count);
  return d;
}

}  // namespace cleanslam::hal::map_file
