#include "cleanslam/calibrate/text.hpp"

#include <cstdio>

namespace cleanslam::calibrate {

std::string fixed(double v, int decimals) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

std::string significant(double v, int digits) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

}  // namespace cleanslam::calibrate
