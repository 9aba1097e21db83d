#pragma once

#include <string>
#include <vector>

// Messages in the tests' checks; one definition, so that test files compiled together in a unity
// build share it.
namespace cleanslam::test {

inline bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// The lines, each ending in a newline: a list of messages as one text.
inline std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& line : lines) {
    s += line + "\n";
  }
  return s;
}

}  // namespace cleanslam::test
