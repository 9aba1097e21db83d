// readers::parse_sensors_yaml (a dataset's calibration) on any text. An error names something; a
// calibration it accepts is written by sensors_yaml_text into a text that reads back to the same
// text.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cleanslam/readers/dataset.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_sensors_yaml: %s\n%s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> warnings;
  const auto r = cleanslam::readers::parse_sensors_yaml(text, "sensors.yaml", &warnings);
  if (!r.ok()) {
    if (r.error().empty()) {
      fail("an empty error message", text);
    }
    return 0;
  }
  const std::string written = cleanslam::readers::sensors_yaml_text(r.value());
  const auto back = cleanslam::readers::parse_sensors_yaml(written, "written.yaml", nullptr);
  if (!back.ok()) {
    fail("sensors_yaml_text wrote a text that does not parse", back.error() + "\n" + written);
  }
  if (cleanslam::readers::sensors_yaml_text(back.value()) != written) {
    fail("the written calibration does not read back to itself", written);
  }
  return 0;
}
