#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "cleanslam/sim_hal/sim/scenario.hpp"
#include "cleanslam/sim_hal/sim/scenario_parameters.hpp"

namespace cleanslam::sim_hal::sim {
namespace {

// A key's value as a comparable text.
std::string value_of(const hal::Parameter<Scenario>& p, const Scenario& s) {
  // The field accessor only takes the address of the member.
  const hal::ParameterField f = p.field(const_cast<Scenario&>(s));  // NOLINT
  if (f.type == hal::ParameterType::kText) {
    return *static_cast<const std::string*>(f.value);
  }
  if (f.type == hal::ParameterType::kNumbers) {
    std::vector<double> v(f.count);
    f.get_numbers(f.value, v.data());
    std::string out;
    for (const double x : v) {
      out += std::to_string(x) + " ";
    }
    return out;
  }
  return std::to_string(hal::get_parameter(p, s));
}

TEST(ScenarioParameters, TheStructsDefaultsAreTheListedDefaultsWithinTheirRanges) {
  const Scenario defaults{};
  std::set<std::string> keys;
  for (const auto& p : scenario_parameters()) {
    EXPECT_TRUE(keys.insert(std::string(p.key)).second) << "listed twice: " << p.key;
    const hal::ParameterType t = hal::parameter_type(p);
    if (t == hal::ParameterType::kText || t == hal::ParameterType::kNumbers) {
      continue;
    }
    EXPECT_EQ(hal::get_parameter(p, defaults), hal::stored_default(p)) << p.key;
    EXPECT_TRUE(hal::parameter_in_range(p, p.default_value)) << p.key;
  }
}

// Every key set through load_scenario's overrides lands in the member it names, and only there.
TEST(ScenarioParameters, EachKeySetsTheMemberItNamesAndNoOther) {
  const auto table = scenario_parameters();
  std::vector<std::string> refused;
  const auto base = load_scenario("default-room");
  ASSERT_TRUE(base.ok()) << base.error();
  for (const auto& p : table) {
    // Values to try, in order: the first the scenario accepts is set.
    std::vector<std::string> values;
    const hal::ParameterType type = hal::parameter_type(p);
    const auto number = [type](double v) {
      return type == hal::ParameterType::kInt || type == hal::ParameterType::kUnsigned64 ||
                     type == hal::ParameterType::kScaledInt64
                 ? std::to_string(static_cast<long long>(v))
                 : std::to_string(v);
    };
    Scenario probe{};
    const hal::ParameterField f = p.field(probe);
    if (type == hal::ParameterType::kText) {
      for (const std::string_view c : f.choices) {
        values.emplace_back(c);
      }
      if (f.choices.empty()) {
        values.emplace_back("some-name");
      }
    } else if (type == hal::ParameterType::kBool) {
      values.emplace_back(hal::get_parameter(p, *base) != 0.0 ? "false" : "true");
    } else {
      for (const double fraction : {0.5, 0.05, 0.001, 0.0001, 1.0}) {
        const double v = p.lo + fraction * (p.hi - p.lo);
        if (type != hal::ParameterType::kNumbers) {
          values.push_back(number(v));
          continue;
        }
        std::string list = "[";
        for (std::size_t i = 0; i < f.count; ++i) {
          list += (i == 0 ? "" : ", ") + std::to_string(v);
        }
        values.push_back(list + "]");
      }
    }
    std::string set;
    readers::Result<Scenario> r = readers::Result<Scenario>::failure("no value tried");
    for (const std::string& value : values) {
      set = std::string(p.key) + "=" + value;
      r = load_scenario("default-room", {set});
      if (r.ok() && value_of(p, *r) != value_of(p, *base)) {
        break;
      }
    }
    if (!r.ok()) {
      refused.push_back(set + ": " + r.error());
      continue;
    }
    EXPECT_NE(value_of(p, *r), value_of(p, *base)) << set;
    for (const auto& q : table) {
      if (&q != &p) {
        EXPECT_EQ(value_of(q, *r), value_of(q, *base)) << "setting " << set << " changed " << q.key;
      }
    }
  }
  std::string all;
  for (const std::string& r : refused) {
    all += r + "\n";
  }
  EXPECT_LE(refused.size(), 0U) << all;
}

}  // namespace
}  // namespace cleanslam::sim_hal::sim
