#include <gtest/gtest.h>

#include <limits>
#include <set>
#include <string>
#include <string_view>

#include "cleanslam/slam_core/parameter_table.hpp"

namespace cleanslam {
namespace {

namespace cs = slam_core;

TEST(ParameterTable, TheStructsDefaultsAreTheListedDefaults) {
  const cs::SlamConfig defaults{};
  for (const auto& p : cs::slam_parameters()) {
    EXPECT_EQ(hal::get_parameter(p, defaults), hal::stored_default(p)) << p.key;
  }
}

TEST(ParameterTable, EveryKeyIsListedOnceWithItsDefaultInRangeAndADoc) {
  std::set<std::string> keys;
  for (const auto& p : cs::slam_parameters()) {
    EXPECT_TRUE(keys.insert(std::string(p.key)).second) << p.key << " listed twice";
    const std::string_view section = p.key.substr(0, p.key.find('.'));
    EXPECT_TRUE(section == "filter" || section == "odometry" || section == "map_management" ||
                section == "frontend" || section == "relocalizer")
        << p.key;
    EXPECT_TRUE(hal::parameter_in_range(p, p.default_value)) << p.key;
    EXPECT_FALSE(p.doc.empty()) << p.key;
    EXPECT_EQ(cs::find_slam_parameter(p.key), &p);
    // A float's bounds round inward: a value read within them stays within them once stored.
    if (hal::parameter_type(p) == hal::ParameterType::kFloat) {
      EXPECT_GE(static_cast<double>(static_cast<float>(p.lo)), p.lo) << p.key;
      EXPECT_LE(static_cast<double>(static_cast<float>(p.hi)), p.hi) << p.key;
    }
  }
  EXPECT_EQ(cs::find_slam_parameter("filter.no_such_key"), nullptr);
}

// Each key sets its own member and no other listed one.
TEST(ParameterTable, EveryKeySetsItsOwnMember) {
  const auto table = cs::slam_parameters();
  for (const auto& p : table) {
    cs::SlamConfig c{};
    const double v = hal::parameter_type(p) == hal::ParameterType::kBool ? 1.0 - p.default_value
                     : hal::parameter_in_range(p, p.hi) && p.hi != p.default_value ? p.hi
                                                                                   : p.lo + 1.0;
    ASSERT_TRUE(hal::parameter_in_range(p, v)) << p.key << " " << v;
    hal::set_parameter(p, c, v);
    for (const auto& q : table) {
      const double expected = &q == &p ? (hal::parameter_type(p) == hal::ParameterType::kFloat
                                              ? static_cast<double>(static_cast<float>(v))
                                              : v)
                                       : hal::stored_default(q);
      EXPECT_EQ(hal::get_parameter(q, c), expected) << "setting " << p.key << " changed " << q.key;
    }
  }
}

TEST(ParameterTable, RangesRejectOutsideNonFiniteAndFractionalIntegers) {
  const auto* eps_trk = cs::find_slam_parameter("filter.eps_trk_px");
  ASSERT_NE(eps_trk, nullptr);
  EXPECT_FALSE(hal::parameter_in_range(*eps_trk, 0.0));  // open below
  EXPECT_TRUE(hal::parameter_in_range(*eps_trk, 100.0));
  EXPECT_FALSE(hal::parameter_in_range(*eps_trk, 100.5));
  EXPECT_FALSE(hal::parameter_in_range(*eps_trk, std::numeric_limits<double>::quiet_NaN()));
  const auto* landmarks = cs::find_slam_parameter("filter.max_landmarks");
  ASSERT_NE(landmarks, nullptr);
  EXPECT_FALSE(hal::parameter_in_range(*landmarks, 2.5));
  EXPECT_FALSE(hal::parameter_in_range(*landmarks, hal::kMaxLandmarks + 1.0));
}

}  // namespace
}  // namespace cleanslam
