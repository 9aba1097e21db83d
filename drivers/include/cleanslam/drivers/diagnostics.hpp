#pragma once

#include <cstdint>
#include <string_view>

namespace cleanslam::drivers {

enum class Severity : std::uint8_t { kInfo, kWarning, kError };

// Where drivers explain themselves: what failed, what was asked, what the device offers.
class Diagnostics {
 public:
  virtual ~Diagnostics() = default;
  virtual void report(Severity severity, std::string_view component, std::string_view message) = 0;
};

// Writes "cleanslam <component>: <severity>: <message>" lines to stderr.
Diagnostics& stderr_diagnostics();

// printf-style report through a fixed buffer (no allocation); long messages are truncated.
void reportf(Diagnostics& sink, Severity severity, std::string_view component, const char* format,
             ...) __attribute__((format(printf, 4, 5)));

}  // namespace cleanslam::drivers
