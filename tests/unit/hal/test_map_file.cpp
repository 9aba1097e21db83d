#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
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
        l.patch[k] = static_cast<float>((k * 7 + static_cast<std::size_t>(i)) % 256) + 0.25F;
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
    EXPECT_EQ(d.offset, kHeaderSize);
    EXPECT_EQ(back->count, 0);

    Bytes dock = b;
    put_f64(dock, 44, bad);  // the dock's y
    reseal(dock);
    d = decode_bytes(dock, *back);
    EXPECT_EQ(d.refusal, Refusal::kNotFinite);
    EXPECT_EQ(d.offset, 36U);

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

}  // namespace
}  // namespace cleanslam::hal::map_file
