#pragma once

#include <string>
#include <string_view>

#include "cleanslam/readers/yaml_document.hpp"

// Dotted keys ("section.sub.key") in a configuration's document.
namespace cleanslam::firmware::yaml_paths {

// The node at the dotted `key` below `root`, or nullptr.
const readers::yaml::Node* find(const readers::yaml::Node& root, std::string_view key);

// The value of the dotted `key` below `root`, made with the mappings on its way (a null node on
// the way becomes a mapping, it and each new entry located at `where`); nullptr, with `error`
// saying why, when a component is empty or a node on the way is not a mapping.
readers::yaml::Node* make(readers::yaml::Node& root, std::string_view key,
                          const readers::yaml::Location& where, std::string& error);

}  // namespace cleanslam::firmware::yaml_paths
