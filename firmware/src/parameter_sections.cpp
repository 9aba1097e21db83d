#include "parameter_sections.hpp"

#include <algorithm>
#include <array>
#include <charconv>

#include "cleanslam/readers/dataset.hpp"

namespace cleanslam::firmware::parameter_sections {

namespace {

template <typename Config>
void add_children(std::span<const slam_core::Parameter<Config>> table, std::string_view prefix,
                  std::vector<std::string>& out) {
  for (const auto& p : table) {
    if (!p.key.starts_with(prefix)) {
      continue;
    }
    const std::string_view rest = p.key.substr(prefix.size());
    const auto dot = rest.find('.');
    if (dot == std::string_view::npos) {
      continue;
    }
    const std::string child(rest.substr(0, dot));
    if (std::find(out.begin(), out.end(), child) == out.end()) {
      out.push_back(child);
    }
  }
}

}  // namespace

std::vector<std::string> children(std::string_view prefix) {
  std::vector<std::string> out;
  add_children(slam_core::slam_parameters(), prefix, out);
  return out;
}

std::string value_text(slam_core::ParameterType type, double value) {
  switch (type) {
    case slam_core::ParameterType::kBool:
      return value != 0.0 ? "true" : "false";
    case slam_core::ParameterType::kInt:
      return std::to_string(static_cast<long long>(value));
    case slam_core::ParameterType::kFloat: {
      std::array<char, 64> buf{};
      const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(),
                                           static_cast<float>(value), std::chars_format::fixed);
      std::string s(buf.data(), ec == std::errc() ? end : buf.data());
      if (s.find_first_of(".ni") == std::string::npos) {
        s += ".0";
      }
      return s;
    }
    case slam_core::ParameterType::kDouble:
      break;
  }
  return readers::format_double(value);
}

}  // namespace cleanslam::firmware::parameter_sections
