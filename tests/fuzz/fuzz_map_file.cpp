// The saved map's decoder (hal::map_file::decode) on any bytes. The first byte picks how the rest
// is read:
//  - bit 0 clear: the rest is the file, so magic, version, layout, count, size and CRC are
//    exercised;
//  - bit 0 set: a valid header whose count the next byte picks (0-3, or about the capacity), with
//    zero flags and reserved words, followed by the rest repeated to the records' size and sealed
//    with a correct CRC, so damaged values reach the plausibility checks.
// A file the decoder accepts holds only finite, plausible values (map_file.hpp's bounds), positive
// semi-definite covariances, distinct ids and known flags, and encodes back to its own bytes; a
// refused one leaves the snapshot empty and names where and why.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <numbers>
#include <vector>

#include "cleanslam/hal/map_file.hpp"

namespace mf = cleanslam::hal::map_file;
namespace lf = cleanslam::hal::log;

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_map_file: %s\n", what);
  std::abort();
}

std::vector<std::uint8_t> sealed_file(const std::uint8_t* data, std::size_t size) {
  // Mostly a few landmarks (a full file costs a CRC over half a megabyte); bytes from 250 on: a
  // full file, one more than it holds, and one less.
  const int pick = size > 0 ? data[0] : 0;
  const int count = pick < 250 ? pick % 4 : mf::kMaxMapLandmarks - 1 + (pick - 250) % 3;
  const std::size_t n = mf::file_size(count);
  std::vector<std::uint8_t> out(n, 0);
  lf::ByteWriter w(out.data(), out.size());
  w.bytes(mf::kMagic.data(), mf::kMagic.size());
  w.u32(mf::kVersion);
  w.u32(static_cast<std::uint32_t>(mf::kHeaderSize));
  w.u32(static_cast<std::uint32_t>(mf::kRecordSize));
  w.u32(static_cast<std::uint32_t>(count));
  // Header flags (24) stay zero, as this version writes them; saved_at, the dock and the records
  // come from the input, the header's reserved word (60) and each record's reserved word stay zero.
  // Copied in blocks: a loop over each byte would spend the run in its own comparisons.
  if (size > 1) {
    const std::size_t end = n - 4;
    for (std::size_t i = 28; i < end;) {
      const std::size_t k = std::min(size - 1, end - i);
      std::memcpy(out.data() + i, data + 1, k);
      i += k;
    }
    std::memset(out.data() + 60, 0, 4);
    for (int r = 0; r < count; ++r) {
      std::memset(out.data() + mf::kHeaderSize + mf::kRecordSize * static_cast<std::size_t>(r) + 12,
                  0, 4);
    }
  }
  lf::ByteWriter crc(out.data() + n - 4, 4);
  crc.u32(lf::crc32_update(0, out.data(), n - 4));
  return out;
}

bool coordinate_ok(double v) {
  return std::isfinite(v) && std::abs(v) <= mf::kMaxAbsCoordinateM;
}

void check_refusal(const mf::Decoded& d, const mf::MapSnapshot& m, std::size_t size) {
  if (m.count != 0) {
    fail("a refused file left landmarks in the snapshot");
  }
  if (d.offset > size) {
    fail("a refusal's offset lies beyond the file");
  }
  if (std::memchr(d.detail.data(), '\0', d.detail.size()) == nullptr) {
    fail("a refusal's detail is not terminated");
  }
  const bool value = d.refusal >= mf::Refusal::kNotFinite;
  if (value != (d.detail[0] != '\0')) {
    fail("a refused value without its detail, or a detail without a refused value");
  }
}

void check_header(const mf::MapSnapshot& m) {
  if (m.saved_at_ns < 0 || m.saved_at_ns > mf::kMaxSavedAtNs) {
    fail("an accepted saved_at_ns is out of range");
  }
  if (!coordinate_ok(m.dock.x_m) || !coordinate_ok(m.dock.y_m) ||
      !(std::abs(m.dock.yaw_rad) <= std::numbers::pi)) {
    fail("an accepted dock pose is out of range");
  }
}

void check_landmark(const mf::MapSnapshot& m, int i) {
  const mf::MapLandmark& l = m.landmarks[static_cast<std::size_t>(i)];
  if (l.id < 0) {
    fail("an accepted id is negative");
  }
  for (int j = 0; j < i; ++j) {
    if (m.landmarks[static_cast<std::size_t>(j)].id == l.id) {
      fail("two accepted landmarks share an id");
    }
  }
  if ((l.flags & ~mf::kKnownRecordFlags) != 0 ||
      ((l.flags & mf::kHasAnchor) != 0 && (l.flags & mf::kHasPatch) == 0)) {
    fail("accepted flags this version does not define");
  }
  for (const double v : l.position_m) {
    if (!coordinate_ok(v)) {
      fail("an accepted landmark position is out of range");
    }
  }
  for (const std::size_t k : {0U, 3U, 5U}) {
    if (!(l.covariance[k] >= 0.0 && l.covariance[k] <= mf::kMaxVarianceM2)) {
      fail("an accepted variance is out of range");
    }
  }
  for (const double v : l.covariance) {
    if (!std::isfinite(v)) {
      fail("an accepted covariance is not finite");
    }
  }
  if (!mf::covariance_ok(l.covariance)) {
    fail("an accepted covariance is not positive semi-definite");
  }
  const bool patch = (l.flags & mf::kHasPatch) != 0;
  if (patch && !(l.first_depth_m > 0.0 && l.first_depth_m <= mf::kMaxAbsCoordinateM)) {
    fail("an accepted first depth is out of range");
  }
  for (const double v : l.anchor_m) {
    if (!coordinate_ok(v)) {
      fail("an accepted anchor is out of range");
    }
  }
  for (const float v : l.patch) {
    if (!(v >= 0.0F && v <= mf::kMaxGrey)) {
      fail("an accepted patch value is outside the grey range");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) {
    return 0;
  }
  std::vector<std::uint8_t> bytes;
  if ((data[0] & 1U) != 0) {
    bytes = sealed_file(data + 1, size - 1);
  } else {
    bytes.assign(data + 1, data + size);
  }
  static const auto snapshot = std::make_unique<mf::MapSnapshot>();
  mf::MapSnapshot& m = *snapshot;
  m.count = -1;
  const mf::Decoded d = mf::decode(bytes.data(), bytes.size(), m);
  if (d.refusal != mf::Refusal::kNone) {
    check_refusal(d, m, bytes.size());
    return 0;
  }
  if (m.count < 0 || m.count > mf::kMaxMapLandmarks || bytes.size() != mf::file_size(m.count)) {
    fail("an accepted file's count does not match its size");
  }
  if (d.detail[0] != '\0') {
    fail("an accepted file carries a refusal's detail");
  }
  check_header(m);
  for (int i = 0; i < m.count; ++i) {
    check_landmark(m, i);
  }
  std::vector<std::uint8_t> again(bytes.size());
  if (mf::encode(m, again.data(), again.size()) != bytes.size()) {
    fail("an accepted snapshot does not encode to its file's size");
  }
  if (again != bytes) {
    fail("an accepted file does not encode back to its own bytes");
  }
  static const auto second = std::make_unique<mf::MapSnapshot>();
  mf::MapSnapshot& m2 = *second;
  if (mf::decode(again.data(), again.size(), m2).refusal != mf::Refusal::kNone) {
    fail("an accepted snapshot, encoded again, is refused");
  }
  if (m2.count != m.count || m2.saved_at_ns != m.saved_at_ns ||
      std::memcmp(&m2.dock, &m.dock, sizeof m.dock) != 0) {
    fail("an accepted snapshot's header does not survive encoding");
  }
  for (int i = 0; i < m.count; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const mf::MapLandmark& a = m.landmarks[k];
    const mf::MapLandmark& b = m2.landmarks[k];
    if (a.id != b.id || a.flags != b.flags ||
        std::memcmp(a.position_m.data(), b.position_m.data(), sizeof a.position_m) != 0 ||
        std::memcmp(a.covariance.data(), b.covariance.data(), sizeof a.covariance) != 0 ||
        std::memcmp(&a.first_depth_m, &b.first_depth_m, sizeof a.first_depth_m) != 0 ||
        std::memcmp(a.anchor_m.data(), b.anchor_m.data(), sizeof a.anchor_m) != 0 ||
        std::memcmp(a.patch.data(), b.patch.data(), sizeof a.patch) != 0) {
      fail("an accepted landmark does not survive encoding");
    }
  }
  return 0;
}
