#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace cleanslam::sim_hal {

// Levenshtein distance: insertions, deletions and substitutions of one character each cost 1.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The valid key nearest to a misspelt one, "" when `valid` is empty or none is close (more than
// a third of the longer name's characters, and more than 2, would have to change).
std::string nearest_key(std::string_view key, const std::vector<std::string>& valid);

// The sentence an unknown-key message ends with: "did you mean filter.eps_ct_m?" when a valid key
// is near, else the list of valid keys. `prefix` is the dotted path of the mapping ("" at the
// root), `rest` what followed the misspelt part of a dotted key (".eps_ct_m" or "").
std::string unknown_key_hint(std::string_view key, const std::vector<std::string>& valid,
                             const std::string& prefix, const std::string& rest);

}  // namespace cleanslam::sim_hal
