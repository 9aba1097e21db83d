// firmware::parse_config on any text, with "key.sub=value" override lines after a NUL byte. Every
// error it reports says something; a configuration it accepts is written by config_text into a
// text that parses back to the same configuration.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cleanslam/firmware/config.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_firmware_config: %s\n%s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::size_t nul = input.find('\0');
  const std::string text = input.substr(0, nul);
  std::vector<std::string> overrides;
  if (nul != std::string::npos) {
    std::size_t start = nul + 1;
    while (start <= input.size()) {
      const std::size_t end = std::min(input.find('\n', start), input.size());
      overrides.push_back(input.substr(start, end - start));
      start = end + 1;
    }
  }
  const cleanslam::firmware::ConfigResult r =
      cleanslam::firmware::parse_config(text, "fuzz.yaml", overrides);
  for (const std::string& e : r.errors) {
    if (e.empty()) {
      fail("an empty error message", text);
    }
  }
  if (!r.ok()) {
    return 0;
  }
  const std::string written = cleanslam::firmware::config_text(r.config);
  const cleanslam::firmware::ConfigResult back =
      cleanslam::firmware::parse_config(written, "written.yaml", {});
  if (!back.ok()) {
    fail("config_text wrote a text that does not parse", back.errors.front() + "\n" + written);
  }
  if (cleanslam::firmware::config_text(back.config) != written) {
    fail("the written configuration does not read back to itself", written);
  }
  return 0;
}
