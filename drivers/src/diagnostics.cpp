#include "cleanslam/drivers/diagnostics.hpp"

#include <cstdarg>
#include <cstdio>

namespace cleanslam::drivers {
namespace {

const char* severity_name(Severity severity) {
  switch (severity) {
    case Severity::kInfo:
      return "info";
    case Severity::kWarning:
      return "warning";
    case Severity::kError:
      return "error";
  }
  return "?";
}

class StderrDiagnostics final : public Diagnostics {
 public:
  void report(Severity severity, std::string_view component, std::string_view message) override {
    std::fprintf(stderr, "cleanslam %.*s: %s: %.*s\n", static_cast<int>(component.size()),
                 component.data(), severity_name(severity), static_cast<int>(message.size()),
                 message.data());
  }
};

}  // namespace

Diagnostics& stderr_diagnostics() {
  static StderrDiagnostics sink;
  return sink;
}

void reportf(Diagnostics& sink, Severity severity, std::string_view component, const char* format,
             ...) {
  char text[512];
  va_list args;
  va_start(args, format);
  const int n = std::vsnprintf(text, sizeof text, format, args);
  va_end(args);
  const std::size_t length =
      n < 0 ? 0
            : (static_cast<std::size_t>(n) < sizeof text ? static_cast<std::size_t>(n)
                                                         : sizeof text - 1);
  sink.report(severity, component, std::string_view(text, length));
}

}  // namespace cleanslam::drivers
