#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <numbers>

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
//          patch f32 x kMapPatchSide^2 (grey levels 0-255).
// Reserved fields, and the depth, anchor and patch when the flags say they are absent, are zero.
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
  kHasAnchor = 1U << 1,  // only with kHasPatch
};
inline constexpr std::uint32_t kKnownRecordFlags = kHasPatch | kHasAnchor;

// What a plausible map holds (docs/architecture.md, "Map file"); the decoder refuses the rest.
// Every coordinate (landmark positions, anchors, the dock) within kMaxAbsCoordinateM of the map's
// origin: ten times the largest std. dev. along a new landmark's ray that the paper uses (eps_ct,
// 1000 m), far beyond any room a cleaning robot maps.
inline constexpr double kMaxAbsCoordinateM = 1e4;
// Variances up to that distance squared; first-sighting depths above zero and up to it.
inline constexpr double kMaxVarianceM2 = kMaxAbsCoordinateM * kMaxAbsCoordinateM;
// Patch values are grey levels of the camera's 8-bit pixels (bilinear samples of them).
inline constexpr float kMaxGrey = 255.0F;
// saved_at_ns is a stamp of the run's clock (a monotonic clock, or a dataset's Unix-epoch stamps):
// not negative and at most 2^62 ns (146 years).
inline constexpr TimeNs kMaxSavedAtNs = TimeNs{1} << 62;

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
    // Fields the flags say are absent are written as zeros (the decoder refuses anything else).
    const bool patch = (l.flags & kHasPatch) != 0;
    const bool anchor = (l.flags & kHasAnchor) != 0;
    w.f64(patch ? l.first_depth_m : 0.0);
    for (const double v : l.anchor_m) {
      w.f64(anchor ? v : 0.0);
    }
    for (const float v : l.patch) {
      w.u32(patch ? std::bit_cast<std::uint32_t>(v) : 0U);
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
  kNotFinite,      // a position, covariance, dock, depth, anchor or patch value is NaN or infinite
  kNotCovariance,  // a landmark covariance that is not positive semi-definite
  kOutOfRange,     // a finite value beyond its plausible range (the bounds above)
  kDuplicateId,    // two landmarks with one id
  kUnknownFlags,   // flag bits this version does not define, or an anchor without a patch
  kNotZero,        // a reserved field, or one its flags say is absent, that is not zero
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
    case Refusal::kOutOfRange:
      return "a value out of its plausible range";
    case Refusal::kDuplicateId:
      return "two landmarks with one id";
    case Refusal::kUnknownFlags:
      return "flags this version does not define";
    case Refusal::kNotZero:
      return "a field that must be zero is not";
  }
  return "unknown";
}

struct Decoded {
  Refusal refusal = Refusal::kNone;
  std::size_t offset = 0;  // where the refused value begins
  std::uint32_t version = 0;
  std::uint32_t count = 0;
  // For a refused value: the landmark, the field, its value and what is allowed, e.g.
  // "landmark 3 (id 17): position_m[0] = 1e+308, allowed -10000 to 10000 m"; else "".
  std::array<char, 256> detail{};
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

namespace decode_detail {

// Which part of the file a refused value belongs to: the header (landmark -1) or a record.
struct Where {
  int landmark = -1;
  std::int64_t id = 0;
};

// Sets the refusal and starts its detail with the place; returns where the detail goes on.
inline std::size_t begin_refusal(Decoded& d, Refusal r, std::size_t at, const Where& w) {
  d.refusal = r;
  d.offset = at;
  const int n = w.landmark < 0 ? std::snprintf(d.detail.data(), d.detail.size(), "header ")
                               : std::snprintf(d.detail.data(), d.detail.size(),
                                               "landmark %d (id %lld): ", w.landmark,
                                               static_cast<long long>(w.id));
  return std::min(static_cast<std::size_t>(std::max(n, 0)), d.detail.size() - 1);
}

// A field's name, with its index when it is one of an array's (index >= 0).
inline std::size_t put_field(Decoded& d, std::size_t k, const char* field, int index) {
  const int n =
      index < 0 ? std::snprintf(d.detail.data() + k, d.detail.size() - k, "%s", field)
                : std::snprintf(d.detail.data() + k, d.detail.size() - k, "%s[%d]", field, index);
  return std::min(k + static_cast<std::size_t>(std::max(n, 0)), d.detail.size() - 1);
}

// True (the refusal set) unless `v` is finite and within [lo, hi].
inline bool value_refused(Decoded& d, std::size_t at, const Where& w, const char* field, int index,
                          double v, double lo, double hi, const char* allowed) {
  if (std::isfinite(v) && v >= lo && v <= hi) {
    return false;
  }
  std::size_t k =
      begin_refusal(d, std::isfinite(v) ? Refusal::kOutOfRange : Refusal::kNotFinite, at, w);
  k = put_field(d, k, field, index);
  std::snprintf(d.detail.data() + k, d.detail.size() - k, " = %.9g, allowed %s", v, allowed);
  return true;
}

// True (the refusal set) unless `bits` are zero; `why` says why the field must be zero.
inline bool nonzero_refused(Decoded& d, std::size_t at, const Where& w, const char* field,
                            int index, std::uint64_t bits, const char* why) {
  if (bits == 0) {
    return false;
  }
  std::size_t k = begin_refusal(d, Refusal::kNotZero, at, w);
  k = put_field(d, k, field, index);
  std::snprintf(d.detail.data() + k, d.detail.size() - k, " = 0x%llx, allowed 0 (%s)",
                static_cast<unsigned long long>(bits), why);
  return true;
}

inline constexpr const char* kCoordinateRange = "-10000 to 10000 m";
inline constexpr const char* kVarianceRange = "0 to 1e+08 m^2";
static_assert(kMaxAbsCoordinateM == 1e4 && kMaxVarianceM2 == 1e8, "update the range texts");

inline bool coordinates_refused(Decoded& d, std::size_t at, const Where& w, const char* field,
                                const std::array<double, 3>& v) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (value_refused(d, at + 8 * i, w, field, static_cast<int>(i), v[i], -kMaxAbsCoordinateM,
                      kMaxAbsCoordinateM, kCoordinateRange)) {
      return true;
    }
  }
  return false;
}

// Finite, variances from 0 to kMaxVarianceM2, positive semi-definite.
inline bool covariance_refused(Decoded& d, std::size_t at, const Where& w,
                               const std::array<double, 6>& c) {
  static constexpr std::array<const char*, 6> kNames{"covariance xx", "covariance xy",
                                                     "covariance xz", "covariance yy",
                                                     "covariance yz", "covariance zz"};
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!std::isfinite(c[i])) {
      return value_refused(d, at + 8 * i, w, kNames[i], -1, c[i], 0.0, 0.0, "a finite value");
    }
  }
  for (const std::size_t i : {0U, 3U, 5U}) {
    if (value_refused(d, at + 8 * i, w, kNames[i], -1, c[i], 0.0, kMaxVarianceM2, kVarianceRange)) {
      if (c[i] < 0.0) {
        d.refusal = Refusal::kNotCovariance;
      }
      return true;
    }
  }
  if (covariance_ok(c)) {
    return false;
  }
  const std::size_t k = begin_refusal(d, Refusal::kNotCovariance, at, w);
  std::snprintf(d.detail.data() + k, d.detail.size() - k,
                "covariance (xx xy xz yy yz zz) = %.9g %.9g %.9g %.9g %.9g %.9g, allowed a "
                "positive semi-definite matrix",
                c[0], c[1], c[2], c[3], c[4], c[5]);
  return true;
}

// The header after the count (offset 24 on): flags, saved_at_ns, the dock, reserved.
inline bool header_refused(Decoded& d, log::ByteReader& r, TimeNs& saved_at, DockPose& dock) {
  const Where w;
  const std::uint32_t flags = r.u32();
  saved_at = r.i64();
  dock.x_m = r.f64();
  dock.y_m = r.f64();
  dock.yaw_rad = r.f64();
  const std::uint32_t reserved = r.u32();
  if (flags != 0) {
    const std::size_t k = begin_refusal(d, Refusal::kUnknownFlags, 24, w);
    std::snprintf(d.detail.data() + k, d.detail.size() - k,
                  "flags = 0x%x, allowed 0 (this version defines none)", flags);
    return true;
  }
  if (saved_at < 0 || saved_at > kMaxSavedAtNs) {
    const std::size_t k = begin_refusal(d, Refusal::kOutOfRange, 28, w);
    std::snprintf(d.detail.data() + k, d.detail.size() - k, "saved_at_ns = %lld, allowed 0 to %lld",
                  static_cast<long long>(saved_at), static_cast<long long>(kMaxSavedAtNs));
    return true;
  }
  return value_refused(d, 36, w, "dock.x_m", -1, dock.x_m, -kMaxAbsCoordinateM, kMaxAbsCoordinateM,
                       kCoordinateRange) ||
         value_refused(d, 44, w, "dock.y_m", -1, dock.y_m, -kMaxAbsCoordinateM, kMaxAbsCoordinateM,
                       kCoordinateRange) ||
         value_refused(d, 52, w, "dock.yaw_rad", -1, dock.yaw_rad, -std::numbers::pi,
                       std::numbers::pi, "-pi to pi") ||
         nonzero_refused(d, 60, w, "reserved", -1, reserved, "reserved");
}

// One record's values after its id, flags and reserved word (read at `at` + 16 on).
inline bool record_values_refused(Decoded& d, log::ByteReader& r, std::size_t at, const Where& w,
                                  MapLandmark& l) {
  for (double& v : l.position_m) {
    v = r.f64();
  }
  for (double& v : l.covariance) {
    v = r.f64();
  }
  l.first_depth_m = r.f64();
  for (double& v : l.anchor_m) {
    v = r.f64();
  }
  for (float& v : l.patch) {
    v = std::bit_cast<float>(r.u32());
  }
  if (coordinates_refused(d, at + 16, w, "position_m", l.position_m) ||
      covariance_refused(d, at + 40, w, l.covariance)) {
    return true;
  }
  const bool patch = (l.flags & kHasPatch) != 0;
  const char* no_patch = "the flags say no patch";
  if (patch ? value_refused(d, at + 88, w, "first_depth_m", -1, l.first_depth_m,
                            std::numeric_limits<double>::denorm_min(), kMaxAbsCoordinateM,
                            "above 0, up to 10000 m")
            : nonzero_refused(d, at + 88, w, "first_depth_m", -1,
                              std::bit_cast<std::uint64_t>(l.first_depth_m), no_patch)) {
    return true;
  }
  if ((l.flags & kHasAnchor) != 0) {
    if (coordinates_refused(d, at + 96, w, "anchor_m", l.anchor_m)) {
      return true;
    }
  } else {
    for (std::size_t i = 0; i < l.anchor_m.size(); ++i) {
      if (nonzero_refused(d, at + 96 + 8 * i, w, "anchor_m", static_cast<int>(i),
                          std::bit_cast<std::uint64_t>(l.anchor_m[i]), "the flags say no anchor")) {
        return true;
      }
    }
  }
  for (std::size_t i = 0; i < l.patch.size(); ++i) {
    const std::size_t p = at + 120 + 4 * i;
    const int index = static_cast<int>(i);
    if (patch ? value_refused(d, p, w, "patch", index, static_cast<double>(l.patch[i]), 0.0,
                              static_cast<double>(kMaxGrey), "0 to 255 (8-bit grey)")
              : nonzero_refused(d, p, w, "patch", index, std::bit_cast<std::uint32_t>(l.patch[i]),
                                no_patch)) {
      return true;
    }
  }
  return false;
}

// One record: id (not negative, not an earlier record's), flags, reserved, then its values.
inline bool record_refused(Decoded& d, log::ByteReader& r, const MapSnapshot& m, std::uint32_t i,
                           MapLandmark& l) {
  const std::size_t at = kHeaderSize + kRecordSize * i;
  l.id = r.i64();
  l.flags = r.u32();
  const std::uint32_t reserved = r.u32();
  const Where w{static_cast<int>(i), l.id};
  if (l.id < 0) {
    const std::size_t k = begin_refusal(d, Refusal::kOutOfRange, at, w);
    std::snprintf(d.detail.data() + k, d.detail.size() - k,
                  "id = %lld, allowed 0 or more (a track id or a slot)",
                  static_cast<long long>(l.id));
    return true;
  }
  for (std::uint32_t j = 0; j < i; ++j) {
    if (m.landmarks[j].id == l.id) {
      const std::size_t k = begin_refusal(d, Refusal::kDuplicateId, at, w);
      std::snprintf(d.detail.data() + k, d.detail.size() - k, "id = %lld, already landmark %u's",
                    static_cast<long long>(l.id), j);
      return true;
    }
  }
  if ((l.flags & ~kKnownRecordFlags) != 0 ||
      ((l.flags & kHasAnchor) != 0 && (l.flags & kHasPatch) == 0)) {
    const std::size_t k = begin_refusal(d, Refusal::kUnknownFlags, at + 8, w);
    std::snprintf(d.detail.data() + k, d.detail.size() - k,
                  "flags = 0x%x, allowed 0x%x (patch), 0x%x (patch, anchor) or 0", l.flags,
                  kHasPatch, kHasPatch | kHasAnchor);
    return true;
  }
  return nonzero_refused(d, at + 12, w, "reserved", -1, reserved, "reserved") ||
         record_values_refused(d, r, at, w, l);
}

}  // namespace decode_detail

// Reads a whole file's bytes into `m`; `m` is left with count 0 unless the file is accepted. A file
// is accepted only when every value is finite and plausible (the bounds above), its covariances
// positive semi-definite, its ids distinct, and every reserved field and every field its flags say
// is absent zero: encoding an accepted snapshot gives back the same bytes.
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
  TimeNs saved_at = 0;
  DockPose dock;
  if (decode_detail::header_refused(d, r, saved_at, dock)) {
    return d;
  }
  for (std::uint32_t i = 0; i < d.count; ++i) {
    if (decode_detail::record_refused(d, r, m, i, m.landmarks[i])) {
      return d;
    }
  }
  m.saved_at_ns = saved_at;
  m.dock = dock;
  m.count = static_cast<int>(d.count);
  return d;
}

}  // namespace cleanslam::hal::map_file
