// cleanslam-calibrate camera FOLDER --board COLSxROWS --square METRES: intrinsics and distortion.
#include <cstdio>
#include <string>

#include "cleanslam/calibrate/camera_calibration.hpp"
#include "cleanslam/calibrate/text.hpp"
#include "command_line.hpp"
#include "commands.hpp"
#include "inputs.hpp"

namespace cleanslam::calibrate {
namespace {

void camera_usage(std::FILE* out) {
  std::fprintf(
      out,
      "usage: %s camera FOLDER|LOG --board COLSxROWS --square METRES [options]\n"
      "  FOLDER      images of a flat checkerboard (png, jpg, pgm, bmp), the board wholly\n"
      "              in view, seen from many angles and over the whole image\n"
      "  LOG         or a log the firmware recorded (cleanslam --record LOG, with\n"
      "              recorder.frame_every 1) while the board was shown so: its frames\n"
      "  --board COLSxROWS  its inner corners (squares - 1) across and down, e.g. 9x6\n"
      "  --square METRES    the side of one square\n"
      "  --min-views N      refuse fewer images with the board found (default 8)\n"
      "  --min-coverage F   refuse corners whose bounding box covers less of the\n"
      "                     image than this fraction (default 0.5)\n"
      "  --max-rms PX       refuse a larger RMS reprojection error (default 1)\n"
      "  --size WxH         write the intrinsics for this image size (the same camera\n"
      "                     at the robot's resolution, e.g. 320x240)\n"
      "%s%s",
      kProgram, kEveryUsage, kOutputUsage);
}

}  // namespace

int camera_command(int argc, char** argv) {
  CommandLine line = parse_command_line(
      argc, argv, 1,
      {"--board", "--square", "--min-views", "--min-coverage", "--max-rms", "--size", "--every"},
      {"-h", "--help"});
  if (line.flags.count("-h") || line.flags.count("--help")) {
    camera_usage(stdout);
    return 0;
  }
  Checkerboard board;
  CameraCalibrationOptions options;
  options.min_views = static_cast<int>(line.number("--min-views", options.min_views));
  options.min_coverage = line.number("--min-coverage", options.min_coverage);
  options.max_rms_px = line.number("--max-rms", options.max_rms_px);
  int width = 0, height = 0;
  if (line.error.empty() && line.positional.size() != 1) {
    line.error = "expected one FOLDER or LOG";
  }
  if (line.error.empty()) {
    read_board(line, board);
  }
  if (line.error.empty() && line.has("--size") &&
      !two_sizes(line.values.at("--size"), width, height)) {
    line.error = "--size: expected WxH, e.g. 320x240, got \"" + line.values.at("--size") + "\"";
  }
  if (!line.error.empty()) {
    tell("camera", line.error);
    camera_usage(stderr);
    return 2;
  }
  const std::string folder = line.positional.front();
  const std::optional<Views> images = read_views("camera", line, folder);
  if (!images) {
    return 1;
  }
  options.progress = [](int done, int total, const std::string& file, bool found) {
    std::fprintf(stderr, "%s camera: [%d/%d] %s: %s\n", kProgram, done, total, file.c_str(),
                 found ? "board found" : "no board");
  };
  auto c = calibrate_camera(*images, board, options);
  if (!c.ok()) {
    tell("camera", c.error());
    return 1;
  }
  const CameraCalibration measured = *c;
  const CameraCalibration out = width > 0 ? scaled_to(measured, width, height) : measured;
  CalibrationResult r;
  r.method = {
      std::string(kProgram) + " camera " + folder + " --board " + line.values.at("--board") +
          " --square " + significant(board.square_m, 6),
      "OpenCV findChessboardCorners, cornerSubPix, calibrateCamera (k3 fixed at 0): " +
          std::to_string(measured.views) + " of " + std::to_string(measured.images) +
          " images used, RMS reprojection error " + fixed(measured.rms_px, 3) + " px;",
      "the corners cover " + fixed(100.0 * measured.coverage, 0) + " % of the " +
          std::to_string(measured.width) + " x " + std::to_string(measured.height) + " image" +
          (width > 0
               ? ", intrinsics scaled to " + std::to_string(width) + " x " + std::to_string(height)
               : std::string()) +
          ".",
  };
  r.keys = {
      {"camera", "width", {double(out.width)}, true, "pixels"},
      {"camera", "height", {double(out.height)}, true, "pixels"},
      {"camera", "fx", {out.fx}, false, "pixels"},
      {"camera", "fy", {out.fy}, false, "pixels"},
      {"camera", "cx", {out.cx}, false, "pixels, from the top-left pixel's centre"},
      {"camera", "cy", {out.cy}, false, ""},
      {"camera",
       "distortion",
       {out.distortion[0], out.distortion[1], out.distortion[2], out.distortion[3]},
       false,
       "k1 k2 p1 p2"},
  };
  std::fprintf(stderr,
               "%s camera: fx %.3f fy %.3f cx %.3f cy %.3f k1 %.4f k2 %.4f p1 %.5f p2 %.5f, RMS "
               "%.3f px, %d views\n",
               kProgram, out.fx, out.fy, out.cx, out.cy, out.distortion[0], out.distortion[1],
               out.distortion[2], out.distortion[3], measured.rms_px, measured.views);
  return emit(kProgram, line, r, {folder});
}

}  // namespace cleanslam::calibrate
