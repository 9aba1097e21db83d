#include "cleanslam/readers/nearest_key.hpp"

#include <algorithm>
#include <numeric>

namespace cleanslam::readers {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), std::size_t{0});
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      const std::size_t substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({above + 1, row[j - 1] + 1, substitute});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string nearest_key(std::string_view key, const std::vector<std::string>& valid) {
  std::string best;
  std::size_t best_distance = 0;
  bool best_extends = false;
  for (const std::string& v : valid) {
    const std::size_t d = edit_distance(key, v);
    // A key that only lacks its unit or suffix ("rate" for "rate_hz") is near however long.
    const bool extends = key.size() >= 3 && v.rfind(key, 0) == 0;
    const std::size_t longer = std::max(key.size(), v.size());
    if (!extends && d > std::max<std::size_t>(2, longer / 2)) {
      continue;
    }
    if (best.empty() || d < best_distance || (d == best_distance && extends && !best_extends)) {
      best = v;
      best_distance = d;
      best_extends = extends;
    }
  }
  return best;
}

std::string unknown_key_hint(std::string_view key, const std::vector<std::string>& valid,
                             const std::string& prefix, const std::string& rest) {
  const std::string near = nearest_key(key, valid);
  const std::string dotted = prefix.empty() ? std::string() : prefix + ".";
  if (!near.empty()) {
    return "did you mean " + dotted + near + rest + "?";
  }
  if (valid.empty()) {
    return dotted.empty() ? std::string("no keys are valid here") : prefix + " takes no keys";
  }
  std::vector<std::string> sorted = valid;
  std::sort(sorted.begin(), sorted.end());
  std::string list;
  for (const std::string& v : sorted) {
    list += (list.empty() ? "" : ", ") + dotted + v;
  }
  return "valid keys: " + list;
}

}  // namespace cleanslam::readers
