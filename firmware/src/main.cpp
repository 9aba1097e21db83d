#include "cleanslam/firmware/program.hpp"

int main(int argc, char** argv) {
  return cleanslam::firmware::program_main(argc, argv);
}
