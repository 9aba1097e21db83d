// The saved map's decoder (hal::map_file::decode) on any bytes. The first byte picks how the rest
// is read:
//  - bit 0 clear: the rest is the file, so magic, version, layout, count, size and CRC are
//    exercised;
//  - bit 0 set: a valid header whose count the next byte picks (0-3, or about the capacity),
//  followed by
//    the rest repeated to the records' size and sealed with a correct CRC, so damaged values reach
//    the finiteness and covariance checks.
// A file the decoder accepts holds only finite values and positive semi-definite covariances, and
// its snapshot survives encoding and decoding again bit for bit; a refused one leaves the snapshot
// empty.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
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
  if (size > 1) {
    for (std::size_t i = 20; i + 4 < n; ++i) {
      out[i] = data[1 + (i - 20) % (size - 1)];
    }
  }
  lf::ByteWriter crc(out.data() + n - 4, 4);
  crc.u32(lf::crc32_update(0, out.data(), n - 4));
  return out;
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
    if (m.count != 0) {
      fail("a refused file left landmarks in the snapshot");
    }
    if (d.offset > bytes.size()) {
      fail("a refusal's offset lies beyond the file");
    }
    return 0;
  }
  if (m.count < 0 || m.count > mf::kMaxMapLandmarks || bytes.size() != mf::file_size(m.count)) {
    fail("an accepted file's count does not match its size");
  }
  for (int i = 0; i < m.count; ++i) {
    const mf::MapLandmark& l = m.landmarks[static_cast<std::size_t>(i)];
    for (const double v : l.position_m) {
      if (!std::isfinite(v)) {
        fail("an accepted landmark position is not finite");
      }
    }
    if (!mf::covariance_ok(l.covariance)) {
      fail("an accepted covariance is not positive semi-definite");
    }
  }
  std::vector<std::uint8_t> again(bytes.size());
  if (mf::encode(m, again.data(), again.size()) != bytes.size()) {
    fail("an accepted snapshot does not encode to its file's size");
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
