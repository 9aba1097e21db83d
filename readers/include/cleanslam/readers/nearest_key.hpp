#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace cleanslam::readers {

// Levenshtein distance: insertions, deletions and substitutions of one character each cost 1.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The valid key nearest to a misspelt one: the fewest edits among those that need at most half
// the longer name's characters (at least 2) changed, or that extend the key ("rate" -> "rate_hz");
// "" when none is that close.
std::string nearest_key(std::string_view key, const std::vector<std::string>& valid);

// The sentence an unknown-key message ends with: "did you mean filter.eps_ct_m?" when a valid key
// is near, else the list of valid keys. `prefix` is the dotted path of the mapping ("" at the
// root), `rest` what followed the misspelt part of a dotted key (".eps_ct_m" or "").
std::string unknown_key_hint(std::string_view key, const std::vector<std::string>& valid,
                             const std::string& prefix, const std::string& rest);

}  // namespace cleanslam::readers
