#include <cstdio>
#include <cstring>

#include "cleanslam/slam_core/version.hpp"

int main(int argc, char** argv) {
  if (argc > 1 && std::strcmp(argv[1], "--version") == 0) {
    std::printf("cleanslam %s\n", cleanslam::slam_core::version());
    return 0;
  }
  std::fprintf(stderr, "cleanslam: the firmware loop is not built yet; try --version\n");
  return 2;
}
