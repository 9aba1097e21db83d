#pragma once

#include <string>
#include <vector>

#include "cleanslam/readers/yaml_document.hpp"

// Keys that configurations and logs written by earlier versions hold. A renamed key is read as
// its present name; a removed key (an always-on switch, an internal made a constant, a setting
// tried and not kept) is accepted only at the value the firmware now always has, so that every
// log recorded before still replays and no configuration silently loses a setting.
namespace cleanslam::firmware::key_history {

// Rewrites `root` (a configuration's document) into today's keys before it is read. Errors name
// the file, line and key; one warning per kind of former key found says which.
void apply(readers::yaml::Node& root, std::vector<std::string>& errors,
           std::vector<std::string>& warnings);

}  // namespace cleanslam::firmware::key_history
