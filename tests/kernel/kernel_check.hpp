#pragma once

#include <cstdarg>
#include <cstdio>
#include <string>

// What a real-kernel checker prints: "KERNEL-TEST <name> PASS|FAIL" after its detail lines.
namespace cleanslam::kernel_test {

class Check {
 public:
  explicit Check(std::string name) : name_(std::move(name)) {}

  __attribute__((format(printf, 3, 4))) bool expect(bool ok, const char* format, ...) {
    if (!ok) {
      ++failures_;
      char text[512];
      va_list args;
      va_start(args, format);
      std::vsnprintf(text, sizeof text, format, args);
      va_end(args);
      std::printf("  %s: FAILED %s\n", name_.c_str(), text);
      std::fflush(stdout);
    }
    return ok;
  }
  __attribute__((format(printf, 2, 3))) void note(const char* format, ...) {
    char text[512];
    va_list args;
    va_start(args, format);
    std::vsnprintf(text, sizeof text, format, args);
    va_end(args);
    std::printf("  %s: %s\n", name_.c_str(), text);
    std::fflush(stdout);
  }
  [[nodiscard]] bool passed() const { return failures_ == 0; }
  int finish() {
    std::printf("KERNEL-TEST %s %s\n", name_.c_str(), passed() ? "PASS" : "FAIL");
    std::fflush(stdout);
    return passed() ? 0 : 1;
  }

 private:
  std::string name_;
  int failures_ = 0;
};

}  // namespace cleanslam::kernel_test
