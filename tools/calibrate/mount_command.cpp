// cleanslam-calibrate mount FOLDER --board COLSxROWS --square METRES --at X,Y --yaw DEG
// --intrinsics SENSORS.yaml: the camera's mount T_body_cam from a board on the floor.
#include <cstdio>
#include <numbers>
#include <string>

#include "cleanslam/calibrate/mount_calibration.hpp"
#include "cleanslam/calibrate/text.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "command_line.hpp"
#include "commands.hpp"
#include "inputs.hpp"

namespace cleanslam::calibrate {
namespace {

void mount_usage(std::FILE* out) {
  std::fprintf(
      out,
      "usage: %s mount FOLDER|LOG --board COLSxROWS --square METRES --at X,Y --yaw DEG\n"
      "       --intrinsics SENSORS.yaml [options]\n"
      "  FOLDER      images (png, jpg, pgm, bmp) from the robot's camera of a flat\n"
      "              checkerboard lying on the floor in front of it, robot and board still\n"
      "  LOG         or a log the firmware recorded so (cleanslam --record LOG): its frames\n"
      "  --board COLSxROWS  its inner corners across and down, e.g. 9x6\n"
      "  --square METRES    the side of one square\n"
      "  --at X,Y    the board's centre (the middle of its inner corners) in the body\n"
      "              frame: metres ahead of the wheel axis' centre, metres to the left\n"
      "  --yaw DEG   the direction of its rows of COLS corners, counter-clockwise from\n"
      "              straight ahead (0 or 180: the rows point ahead; 90: to the left)\n"
      "  --intrinsics FILE  a sensors.yaml with the camera's calibrated intrinsics\n"
      "  --max-rms PX       refuse a larger reprojection error (default 2)\n"
      "%s%s",
      kProgram, kEveryUsage, kOutputUsage);
}

}  // namespace

int mount_command(int argc, char** argv) {
  CommandLine line = parse_command_line(
      argc, argv, 1,
      {"--board", "--square", "--at", "--yaw", "--intrinsics", "--max-rms", "--every"},
      {"-h", "--help"});
  if (line.flags.count("-h") || line.flags.count("--help")) {
    mount_usage(stdout);
    return 0;
  }
  Checkerboard board;
  BoardOnFloor spot;
  spot.yaw_rad = line.number("--yaw", 0.0) * std::numbers::pi / 180.0;
  const double max_rms = line.number("--max-rms", 2.0);
  if (line.error.empty() && line.positional.size() != 1) {
    line.error = "expected one FOLDER or LOG";
  }
  if (line.error.empty()) {
    read_board(line, board);
  }
  char tail = 0;
  if (line.error.empty() &&
      (!line.has("--at") || std::sscanf(line.values.at("--at").c_str(), "%lf,%lf%c", &spot.x_m,
                                        &spot.y_m, &tail) != 2)) {
    line.error = "--at X,Y: the board's centre in the body frame is needed, e.g. --at 0.6,0";
  }
  if (line.error.empty() && (!line.has("--yaw") || !line.has("--intrinsics"))) {
    line.error = "--yaw DEG and --intrinsics SENSORS.yaml are needed";
  }
  if (!line.error.empty()) {
    tell("mount", line.error);
    mount_usage(stderr);
    return 2;
  }
  const std::string intrinsics_file = line.values.at("--intrinsics");
  auto intrinsics = readers::read_sensors_yaml(intrinsics_file);
  if (!intrinsics.ok()) {
    tell("mount", intrinsics.error());
    return 1;
  }
  const std::string folder = line.positional.front();
  const std::optional<Views> images = read_views("mount", line, folder);
  if (!images) {
    return 1;
  }
  auto m = calibrate_mount(*images, board, spot, intrinsics->camera, max_rms);
  if (!m.ok()) {
    tell("mount", m.error());
    return 1;
  }
  CalibrationResult r;
  r.method = {
      std::string(kProgram) + " mount " + folder + " --board " + line.values.at("--board") +
          " --square " + significant(board.square_m, 6) + " --at " + line.values.at("--at") +
          " --yaw " + line.values.at("--yaw"),
      "OpenCV solvePnP of the board's corners in the body frame (on the floor, centre and yaw as "
      "measured)",
      "through the intrinsics of " + intrinsics_file + ": " + std::to_string(m->views) +
          " views, RMS reprojection error " + fixed(m->rms_px, 3) + " px; the camera is " +
          fixed(m->height_m, 3) + " m up,",
      "its optical axis " + fixed(m->tilt_deg, 2) + " deg above the horizontal and " +
          fixed(m->yaw_deg, 2) + " deg left of straight ahead.",
  };
  r.keys = {{"camera",
             "T_body_cam",
             {m->T_body_cam.begin(), m->T_body_cam.end()},
             false,
             "row-major, the optical frame in the body frame"}};
  tell("mount", "camera " + fixed(m->T_body_cam[3], 3) + ", " + fixed(m->T_body_cam[7], 3) + ", " +
                    fixed(m->T_body_cam[11], 3) + " m, tilt " + fixed(m->tilt_deg, 2) +
                    " deg, yaw " + fixed(m->yaw_deg, 2) + " deg, RMS " + fixed(m->rms_px, 3) +
                    " px");
  return emit(kProgram, line, r, {folder});
}

}  // namespace cleanslam::calibrate
