// cleanslam-calibrate wheels|gyro|camera|mount ...: measures a robot's calibration (the keys of
// sensors.yaml and of the firmware configuration's `calibration` section) from recordings.
#include <cstdio>
#include <string_view>

#include "commands.hpp"

namespace {

void usage(std::FILE* out) {
  std::fprintf(out,
               "usage: cleanslam-calibrate COMMAND ... (COMMAND --help says more)\n"
               "  wheels DATASET --straight METRES  ticks per metre and wheel base from a\n"
               "                                    straight drive and turns in place\n"
               "  gyro DATASET                      the gyro's bias and noise density from a\n"
               "                                    standstill (Allan deviation)\n"
               "  camera FOLDER --board COLSxROWS --square METRES\n"
               "                                    intrinsics and distortion from checkerboard\n"
               "                                    images\n"
               "  mount FOLDER --board COLSxROWS --square METRES --at X,Y --yaw DEG\n"
               "        --intrinsics SENSORS.yaml   the camera's mount T_body_cam from a board\n"
               "                                    on the floor\n"
               "A DATASET or FOLDER may also be a log the firmware recorded (cleanslam --record\n"
               "LOG): its gyro and encoder records, or its frames' images.\n");
}

}  // namespace

int main(int argc, char** argv) {
  namespace cal = cleanslam::calibrate;
  if (argc < 2) {
    usage(stderr);
    return 2;
  }
  const std::string_view command = argv[1];
  if (command == "-h" || command == "--help") {
    usage(stdout);
    return 0;
  }
  if (command == "wheels") {
    return cal::wheels_command(argc - 1, argv + 1);
  }
  if (command == "gyro") {
    return cal::gyro_command(argc - 1, argv + 1);
  }
  if (command == "camera") {
    return cal::camera_command(argc - 1, argv + 1);
  }
  if (command == "mount") {
    return cal::mount_command(argc - 1, argv + 1);
  }
  std::fprintf(stderr, "cleanslam-calibrate: unknown command \"%s\"\n", argv[1]);
  usage(stderr);
  return 2;
}
