// A dataset folder's CSV readers (the dataset format's six tables) on any text: the first byte
// picks the file (gyro, encoders, camera, features, groundtruth, lift), the rest is its content. A
// reader either returns rows or an error that names something, never crashes.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "cleanslam/readers/dataset.hpp"

namespace sh = cleanslam::readers;

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_dataset_csv: %s\n", what);
  std::abort();
}

const std::string& scratch_path() {
  static const std::string path =
      "/tmp/cleanslam_fuzz_dataset_" + std::to_string(::getpid()) + ".csv";
  return path;
}

template <typename R>
void expect_rows_or_error(const R& r) {
  if (!r.ok() && r.error().empty()) {
    fail("a reader failed without an error message");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) {
    return 0;
  }
  const std::string& path = scratch_path();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) {
    fail("cannot write the scratch file");
  }
  const bool written = std::fwrite(data + 1, 1, size - 1, f) == size - 1;
  std::fclose(f);
  if (!written) {
    fail("cannot write the scratch file");
  }
  switch (data[0] % 6) {
    case 0:
      expect_rows_or_error(sh::read_gyro_csv(path));
      break;
    case 1:
      expect_rows_or_error(sh::read_encoders_csv(path));
      break;
    case 2:
      expect_rows_or_error(sh::read_camera_csv(path));
      break;
    case 3:
      expect_rows_or_error(sh::read_features_csv(path));
      break;
    case 4:
      expect_rows_or_error(sh::read_groundtruth_csv(path));
      break;
    default:
      expect_rows_or_error(sh::read_lift_csv(path));
      break;
  }
  std::remove(path.c_str());
  return 0;
}
