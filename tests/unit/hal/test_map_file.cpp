#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cleanslam/hal/map_file.hpp"

namespace cleanslam::hal::map_file {
namespace {

using Bytes = std::vector<std::uint8_t>;

std::unique_ptr<MapSnapshot> sample_map(int count) {
  auto m = std::make_unique<MapSnapshot>();
  m->saved_at_ns = 123'000'000'000;
  m->dock = DockPose{0.25, -0.5, 0.1};
  m->count = count;
  for (int i = 0; i < count; ++i) {
    MapLandmark& l = m->landmarks[static_cast<std::size_t>(i)];
    l.id = 1000 + i;
    l.flags = i % 2 == 0 ? (kHasPatch | kHasAnchor) : 0U;
    l.position_m = {0.5 * i, 1.0 - i, 0.3};
    l.covariance = {0.02, 0.001, -0.002, 0.03, 0.0005, 0.01};
    if ((l.flags & kHasPatch) != 0) {
      l.first_depth_m = 1.5 + i;
      l.anchor_m = {0.1, 0.2 * i, 0.1};
      for (std::size_t k = 0; k < l.patch.size(); ++k) {
        l.patch[k] = static_cast<float>((k * 7 + static_cast<std::size_t>(i)) % 255) + 0.25F;
      }
    }
  }
  return m;
}

Bytes encoded(const MapSnapshot& m) {
  Bytes b(file_size(m.count));
  EXPECT_EQ(encode(m, b.data(), b.size()), b.size());
  return b;
}

// Recomputes the trailing CRC, so that a changed value reaches the value checks.
void put_le(Bytes& b, std::size_t at, std::uint64_t v, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    b.at(at + i) = static_cast<std::uint8_t>(v >> (8 * i));
  }
}

void reseal(Bytes& b) {
  put_le(b, b.size() - 4, log::crc32_update(0, b.data(), b.size() - 4), 4);
}

void put_f64(Bytes& b, std::size_t at, double v) {
  put_le(b, at, std::bit_cast<std::uint64_t>(v), 8);
}

Decoded decode_bytes(const Bytes& b, MapSnapshot& out) {
  return decode(b.data(), b.size(), out);
}

constexpr std::size_t kPositionAt = kHeaderSize + 16;
constexpr std::size_t kCovarianceAt = kPositionAt + 24;

TEST(MapFile, RoundTripKeepsEveryValueBitForBit) {
  const auto m = sample_map(5);
  const Bytes b = encoded(*m);
  EXPECT_EQ(b.size(), kHeaderSize + 5 * kRecordSize + 4);
  auto back = std::make_unique<MapSnapshot>();
  const Decoded d = decode_bytes(b, *back);
  ASSERT_EQ(d.refusal, Refusal::kNone) << to_string(d.refusal);
  EXPECT_EQ(d.count, 5U);
  EXPECT_EQ(back->count, 5);
  EXPECT_EQ(back->saved_at_ns, m->saved_at_ns);
  EXPECT_EQ(back->dock.x_m, 0.25);
  EXPECT_EQ(back->dock.y_m, -0.5);
  EXPECT_EQ(back->dock.yaw_rad, 0.1);
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(back->landmarks[static_cast<std::size_t>(i)] ==
                m->landmarks[static_cast<std::size_t>(i)])
        << "landmark " << i;
  }
}

TEST(MapFile, AnEmptyMapIsAValidFile) {
  const auto m = sample_map(0);
  const Bytes b = encoded(*m);
  auto back = std::make_unique<MapSnapshot>();
  EXPECT_EQ(decode_bytes(b, *back).refusal, Refusal::kNone);
  EXPECT_EQ(back->count, 0);
}

TEST(MapFile, EncodeRefusesWhatDoesNotFit) {
  const auto m = sample_map(2);
  Bytes small(file_size(2) - 1);
  EXPECT_EQ(encode(*m, small.data(), small.size()), 0U);
  m->count = kMaxMapLandmarks + 1;
  Bytes big(file_size(kMaxMapLandmarks + 1));
  EXPECT_EQ(encode(*m, big.data(), big.size()), 0U);
}

TEST(MapFile, ACutAtEvery64thByteIsRefusedAndLeavesNoLandmarks) {
  const Bytes b = encoded(*sample_map(3));
  auto back = std::make_unique<MapSnapshot>();
  for (std::size_t k = 0; k < b.size(); k += 64) {
    const Bytes cut(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(k));
    back->count = 7;
    const Decoded d = decode_bytes(cut, *back);
    EXPECT_TRUE(d.refusal == Refusal::kTooShort || d.refusal == Refusal::kSize)
        << "cut at " << k << ": " << to_string(d.refusal);
    EXPECT_EQ(back->count, 0) << "cut at " << k;
  }
  Bytes longer = b;
  longer.push_back(0);
  EXPECT_EQ(decode_bytes(longer, *back).refusal, Refusal::kSize);
}

TEST(MapFile, AFlippedByteAnywhereIsRefused) {
  const Bytes b = encoded(*sample_map(3));
  auto back = std::make_unique<MapSnapshot>();
  int refused = 0;
  for (std::size_t k = 0; k < b.size(); k += 64) {
    for (const int mask : {0x01, 0x80, 0xFF}) {
      Bytes flipped = b;
      flipped[k] = static_cast<std::uint8_t>(flipped[k] ^ mask);
      const Decoded d = decode_bytes(flipped, *back);
      EXPECT_NE(d.refusal, Refusal::kNone) << "byte " << k << " mask " << mask;
      EXPECT_EQ(back->count, 0);
      refused += d.refusal != Refusal::kNone ? 1 : 0;
    }
  }
  EXPECT_GT(refused, 0);
}

TEST(MapFile, EachHeaderRefusalIsNamedWithItsOffset) {
  const Bytes b = encoded(*sample_map(1));
  auto back = std::make_unique<MapSnapshot>();
  Bytes other = b;
  other[0] = 'X';
  Decoded d = decode_bytes(other, *back);
  EXPECT_EQ(d.refusal, Refusal::kNotAMap);
  EXPECT_EQ(d.offset, 0U);

  Bytes version = b;
  version[8] = 2;
  d = decode_bytes(version, *back);
  EXPECT_EQ(d.refusal, Refusal::kOtherVersion);
  EXPECT_EQ(d.version, 2U);
  EXPECT_EQ(d.offset, 8U);

  Bytes layout = b;
  layout[16] ^= 1;
  EXPECT_EQ(decode_bytes(layout, *back).refusal, Refusal::kLayout);

  Bytes many = b;
  put_le(many, 20, static_cast<std::uint64_t>(kMaxMapLandmarks) + 1, 4);
  d = decode_bytes(many, *back);
  EXPECT_EQ(d.refusal, Refusal::kTooManyLandmarks);
  EXPECT_EQ(d.offset, 20U);

  Bytes damaged = b;
  damaged[kHeaderSize + 100] ^= 0x10;
  d = decode_bytes(damaged, *back);
  EXPECT_EQ(d.refusal, Refusal::kCrc);
  EXPECT_EQ(d.offset, b.size() - 4);
  EXPECT_STREQ(to_string(d.refusal), "CRC mismatch (damaged)");
}

TEST(MapFile, NonFiniteValuesAreRefusedEvenWithAValidCrc) {
  const Bytes b = encoded(*sample_map(2));
  auto back = std::make_unique<MapSnapshot>();
  for (const double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    Bytes p = b;
    put_f64(p, kPositionAt + 8, bad);
    reseal(p);
    Decoded d = decode_bytes(p, *back);
    EXPECT_EQ(d.refusal, Refusal::kNotFinite);
    EXPECT_EQ(d.offset, kPositionAt + 8);
    EXPECT_EQ(back->count, 0);

    Bytes dock = b;
    put_f64(dock, 44, bad);  // the dock's y
    reseal(dock);
    d = decode_bytes(dock, *back);
    EXPECT_EQ(d.refusal, Refusal::kNotFinite);
    EXPECT_EQ(d.offset, 44U);

    Bytes patch = b;
    put_le(patch, kHeaderSize + kRecordSize - 4,
           std::bit_cast<std::uint32_t>(static_cast<float>(bad)), 4);
    reseal(patch);
    EXPECT_EQ(decode_bytes(patch, *back).refusal, Refusal::kNotFinite);
  }
}

TEST(MapFile, AnIndefiniteCovarianceIsRefused) {
  const Bytes b = encoded(*sample_map(2));
  auto back = std::make_unique<MapSnapshot>();
  Bytes negative = b;
  put_f64(negative, kCovarianceAt, -0.02);
  reseal(negative);
  Decoded d = decode_bytes(negative, *back);
  EXPECT_EQ(d.refusal, Refusal::kNotCovariance);
  EXPECT_EQ(d.offset, kCovarianceAt);

  // Leading minors all zero, yet indefinite: y and z correlated with both variances zero.
  Bytes hidden = b;
  for (std::size_t k = 0; k < 6; ++k) {
    put_f64(hidden, kCovarianceAt + 8 * k, k == 4 ? 0.01 : 0.0);
  }
  reseal(hidden);
  EXPECT_EQ(decode_bytes(hidden, *back).refusal, Refusal::kNotCovariance);
  EXPECT_FALSE(covariance_ok({0.0, 0.0, 0.0, 0.0, 0.01, 0.0}));
  EXPECT_FALSE(covariance_ok({0.01, 0.0, 0.02, 0.04, 0.0, 0.01}));  // x-z correlation above one
  EXPECT_TRUE(covariance_ok({0.0, 0.0, 0.0, 0.0, 0.0, 0.0}));

  // Positive variances, but a correlation above one.
  Bytes correlated = b;
  put_f64(correlated, kCovarianceAt + 8, 0.5);
  reseal(correlated);
  EXPECT_EQ(decode_bytes(correlated, *back).refusal, Refusal::kNotCovariance);
}

TEST(MapFile, FieldsTheFlagsSayAreAbsentComeBackAsZero) {
  auto m = sample_map(2);
  MapLandmark& l = m->landmarks[1];
  l.flags = 0;
  l.first_depth_m = std::numeric_limits<double>::quiet_NaN();
  l.anchor_m = {std::numeric_limits<double>::infinity(), 1.0, 2.0};
  const Bytes b = encoded(*m);
  auto back = std::make_unique<MapSnapshot>();
  ASSERT_EQ(decode_bytes(b, *back).refusal, Refusal::kNone);
  EXPECT_EQ(back->landmarks[1].first_depth_m, 0.0);
  EXPECT_EQ(back->landmarks[1].anchor_m, (std::array<double, 3>{}));
}

constexpr std::size_t kRecord1At = kHeaderSize + kRecordSize;
constexpr std::size_t kDepthAt = kHeaderSize + 88;
constexpr std::size_t kAnchorAt = kHeaderSize + 96;
constexpr std::size_t kPatchAt = kHeaderSize + 120;

void put_f32(Bytes& b, std::size_t at, float v) {
  put_le(b, at, std::bit_cast<std::uint32_t>(v), 4);
}

struct ValueCase {
  const char* name;
  std::function<void(Bytes&)> edit;
  Refusal refusal;
  std::size_t offset;
  const char* detail;  // the whole detail the refusal carries
};

// Each value the issue found accepted with a valid CRC, and the other plausibility checks: refused
// with the field, its value and what is allowed; the snapshot left empty.
TEST(MapFile, ImplausibleValuesAreRefusedNamingTheFieldAndTheValue) {
  const Bytes b = encoded(*sample_map(2));
  const std::vector<ValueCase> cases{
      {"position 1e308", [](Bytes& x) { put_f64(x, kPositionAt, 1e308); }, Refusal::kOutOfRange,
       kPositionAt, "landmark 0 (id 1000): position_m[0] = 1e+308, allowed -10000 to 10000 m"},
      {"position z -1e4 - 1", [](Bytes& x) { put_f64(x, kPositionAt + 16, -10001.0); },
       Refusal::kOutOfRange, kPositionAt + 16,
       "landmark 0 (id 1000): position_m[2] = -10001, allowed -10000 to 10000 m"},
      {"variance 1e308", [](Bytes& x) { put_f64(x, kCovarianceAt + 24, 1e308); },
       Refusal::kOutOfRange, kCovarianceAt + 24,
       "landmark 0 (id 1000): covariance yy = 1e+308, allowed 0 to 1e+08 m^2"},
      {"negative variance", [](Bytes& x) { put_f64(x, kCovarianceAt + 40, -1.0); },
       Refusal::kNotCovariance, kCovarianceAt + 40,
       "landmark 0 (id 1000): covariance zz = -1, allowed 0 to 1e+08 m^2"},
      {"covariance NaN",
       [](Bytes& x) { put_f64(x, kCovarianceAt + 8, std::numeric_limits<double>::quiet_NaN()); },
       Refusal::kNotFinite, kCovarianceAt + 8,
       "landmark 0 (id 1000): covariance xy = nan, allowed a finite value"},
      {"correlation above one", [](Bytes& x) { put_f64(x, kCovarianceAt + 8, 0.5); },
       Refusal::kNotCovariance, kCovarianceAt,
       "landmark 0 (id 1000): covariance (xx xy xz yy yz zz) = 0.02 0.5 -0.002 0.03 0.0005 0.01, "
       "allowed a positive semi-definite matrix"},
      {"dock 1e308", [](Bytes& x) { put_f64(x, 36, 1e308); }, Refusal::kOutOfRange, 36,
       "header dock.x_m = 1e+308, allowed -10000 to 10000 m"},
      {"dock yaw 4 rad", [](Bytes& x) { put_f64(x, 52, 4.0); }, Refusal::kOutOfRange, 52,
       "header dock.yaw_rad = 4, allowed -pi to pi"},
      {"negative first depth", [](Bytes& x) { put_f64(x, kDepthAt, -1.5); }, Refusal::kOutOfRange,
       kDepthAt, "landmark 0 (id 1000): first_depth_m = -1.5, allowed above 0, up to 10000 m"},
      {"zero first depth", [](Bytes& x) { put_f64(x, kDepthAt, 0.0); }, Refusal::kOutOfRange,
       kDepthAt, "landmark 0 (id 1000): first_depth_m = 0, allowed above 0, up to 10000 m"},
      {"anchor 1e308", [](Bytes& x) { put_f64(x, kAnchorAt + 8, 1e308); }, Refusal::kOutOfRange,
       kAnchorAt + 8, "landmark 0 (id 1000): anchor_m[1] = 1e+308, allowed -10000 to 10000 m"},
      {"patch 3e38", [](Bytes& x) { put_f32(x, kPatchAt + 28, 3e38F); }, Refusal::kOutOfRange,
       kPatchAt + 28,
       "landmark 0 (id 1000): patch[7] = 3.00000001e+38, allowed 0 to 255 (8-bit grey)"},
      {"patch -1", [](Bytes& x) { put_f32(x, kPatchAt, -1.0F); }, Refusal::kOutOfRange, kPatchAt,
       "landmark 0 (id 1000): patch[0] = -1, allowed 0 to 255 (8-bit grey)"},
      {"saved_at INT64_MIN",
       [](Bytes& x) {
         put_le(x, 28, static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::min()), 8);
       },
       Refusal::kOutOfRange, 28,
       "header saved_at_ns = -9223372036854775808, allowed 0 to 4611686018427387904"},
      {"saved_at INT64_MAX",
       [](Bytes& x) {
         put_le(x, 28, static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()), 8);
       },
       Refusal::kOutOfRange, 28,
       "header saved_at_ns = 9223372036854775807, allowed 0 to 4611686018427387904"},
      {"duplicate id", [](Bytes& x) { put_le(x, kRecord1At, 1000, 8); }, Refusal::kDuplicateId,
       kRecord1At, "landmark 1 (id 1000): id = 1000, already landmark 0's"},
      {"negative id", [](Bytes& x) { put_le(x, kRecord1At, ~std::uint64_t{0}, 8); },
       Refusal::kOutOfRange, kRecord1At,
       "landmark 1 (id -1): id = -1, allowed 0 or more (a track id or a slot)"},
      {"unknown record flag", [](Bytes& x) { put_le(x, kHeaderSize + 8, 0x7, 4); },
       Refusal::kUnknownFlags, kHeaderSize + 8,
       "landmark 0 (id 1000): flags = 0x7, allowed 0x1 (patch), 0x3 (patch, anchor) or 0"},
      {"anchor without patch", [](Bytes& x) { put_le(x, kRecord1At + 8, kHasAnchor, 4); },
       Refusal::kUnknownFlags, kRecord1At + 8,
       "landmark 1 (id 1001): flags = 0x2, allowed 0x1 (patch), 0x3 (patch, anchor) or 0"},
      {"header flag", [](Bytes& x) { put_le(x, 24, 0x80000000U, 4); }, Refusal::kUnknownFlags, 24,
       "header flags = 0x80000000, allowed 0 (this version defines none)"},
      {"header reserved", [](Bytes& x) { put_le(x, 60, 1, 4); }, Refusal::kNotZero, 60,
       "header reserved = 0x1, allowed 0 (reserved)"},
      {"record reserved", [](Bytes& x) { put_le(x, kRecord1At + 12, 9, 4); }, Refusal::kNotZero,
       kRecord1At + 12, "landmark 1 (id 1001): reserved = 0x9, allowed 0 (reserved)"},
      {"depth without patch", [](Bytes& x) { put_f64(x, kRecord1At + 88, 2.0); }, Refusal::kNotZero,
       kRecord1At + 88,
       "landmark 1 (id 1001): first_depth_m = 0x4000000000000000, allowed 0 (the flags say no "
       "patch)"},
      {"patch without patch", [](Bytes& x) { put_f32(x, kRecord1At + 120 + 40, 1.0F); },
       Refusal::kNotZero, kRecord1At + 120 + 40,
       "landmark 1 (id 1001): patch[10] = 0x3f800000, allowed 0 (the flags say no patch)"},
  };
  auto back = std::make_unique<MapSnapshot>();
  for (const ValueCase& c : cases) {
    Bytes x = b;
    c.edit(x);
    reseal(x);
    back->count = 9;
    const Decoded d = decode_bytes(x, *back);
    EXPECT_EQ(d.refusal, c.refusal) << c.name << ": " << to_string(d.refusal);
    EXPECT_EQ(d.offset, c.offset) << c.name;
    EXPECT_EQ(std::string(d.detail.data()), c.detail) << c.name;
    EXPECT_EQ(back->count, 0) << c.name;
  }
}

TEST(MapFile, ValuesAtTheBoundsAreAccepted) {
  auto m = sample_map(2);
  m->saved_at_ns = kMaxSavedAtNs;
  m->dock = DockPose{-kMaxAbsCoordinateM, kMaxAbsCoordinateM, -std::numbers::pi};
  MapLandmark& l = m->landmarks[0];
  l.position_m = {kMaxAbsCoordinateM, -kMaxAbsCoordinateM, 0.0};
  l.covariance = {kMaxVarianceM2, 0.0, 0.0, kMaxVarianceM2, 0.0, 0.0};
  l.first_depth_m = kMaxAbsCoordinateM;
  l.patch.front() = 0.0F;
  l.patch.back() = kMaxGrey;
  m->landmarks[1].id = 0;
  const Bytes b = encoded(*m);
  auto back = std::make_unique<MapSnapshot>();
  const Decoded d = decode_bytes(b, *back);
  EXPECT_EQ(d.refusal, Refusal::kNone) << to_string(d.refusal) << ": " << d.detail.data();
  EXPECT_EQ(back->count, 2);
  EXPECT_STREQ(d.detail.data(), "");
}

// The decoder accepts only what the encoder writes: an accepted file encodes back to its bytes.
TEST(MapFile, AnAcceptedFileEncodesBackToTheSameBytes) {
  const Bytes b = encoded(*sample_map(4));
  auto back = std::make_unique<MapSnapshot>();
  ASSERT_EQ(decode_bytes(b, *back).refusal, Refusal::kNone);
  EXPECT_EQ(encoded(*back), b);
}

}  // namespace
}  // namespace cleanslam::hal::map_file
