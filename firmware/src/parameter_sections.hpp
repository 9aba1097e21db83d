#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "cleanslam/firmware/config.hpp"
#include "cleanslam/slam_core/parameter_table.hpp"

// The estimator's sections of the configuration as the parameter table lays them out: the keys
// of slam_core::slam_parameters(), nested at their dots.
namespace cleanslam::firmware::parameter_sections {

// The key's name below `prefix` ("frontend.harris." and "frontend.harris.k" -> "k") when it is
// directly below it, else empty.
inline std::string_view leaf_name(std::string_view key, std::string_view prefix) {
  if (!key.starts_with(prefix)) {
    return {};
  }
  const std::string_view rest = key.substr(prefix.size());
  return rest.find('.') == std::string_view::npos ? rest : std::string_view{};
}

// The mappings directly below `prefix` ("" gives the top-level sections), in the tables' order.
std::vector<std::string> children(std::string_view prefix);

// A value as the configuration writes it (a float with the digits that read back to it).
std::string value_text(slam_core::ParameterType type, double value);

}  // namespace cleanslam::firmware::parameter_sections
