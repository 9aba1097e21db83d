// cleanslam-track DATASET --out FILE [--overlay DIR] [options]
//
// Runs the vision front end alone (Harris, search regions, LK/ZSSD/NCC tracking with patch
// scale prediction, JCBB, map management) on a dataset's camera images, with an image-only
// motion model in place of the EKF, and writes the tracks as features.csv
// (t_ns,track_id,u_px,v_px: the inliers of every frame that passes JCBB, and each new landmark
// where it was taken). --overlay DIR writes one PNG per frame with the tracks, search regions and
// inlier/outlier marks, captioned with the frame's time and a legend.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/gray_image.hpp"
#include "cleanslam/slam_core/frontend/frame_pipeline.hpp"
#include "cleanslam/tools/output_paths.hpp"
#include "image_only_estimator.hpp"
#include "overlay.hpp"

namespace fe = cleanslam::slam_core::frontend;
namespace tr = cleanslam::tools::track;

namespace {

void usage(std::FILE* to) {
  std::fprintf(
      to,
      "usage: cleanslam-track DATASET --out FILE [--overlay DIR] [--force] [--min-ncc X]\n"
      "                       [--sigma-motion PX] [--max-frames N]\n"
      "  DATASET           dataset folder with sensors.yaml and cam0/data.csv\n"
      "  --out FILE        features.csv to write (t_ns,track_id,u_px,v_px); its folder is\n"
      "                    created; refused when it exists (unless --force) or lies in\n"
      "                    DATASET\n"
      "  --overlay DIR     write DIR/NNNNNN.png per frame: search regions (yellow),\n"
      "                    inliers (green), outliers and misses (red), new (cyan),\n"
      "                    with the frame's number, time and counts and a legend\n"
      "                    below; a small image is drawn twice its size; DIR is\n"
      "                    created, refused when not empty (unless --force)\n"
      "  --force           replace FILE, and the NNNNNN.png of an earlier run in DIR\n"
      "  --min-ncc X       NCC a match must clear (default 0.8)\n"
      "  --sigma-motion PX image motion between frames, 1 sigma (default 12)\n"
      "  --max-frames N    stop after N frames\n");
}

bool parse_double(const char* flag, const char* text, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(out)) {
    std::fprintf(stderr, "cleanslam-track: %s expects a number, got '%s'\n", flag, text);
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dataset;
  std::string out_path;
  std::string overlay_dir;
  double min_ncc = 0.8;
  double sigma_motion = 12.0;
  double max_frames = -1.0;
  bool force = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    }
    if ((a == "--out" || a == "--overlay" || a == "--min-ncc" || a == "--sigma-motion" ||
         a == "--max-frames") &&
        !has_value) {
      std::fprintf(stderr, "cleanslam-track: %s needs a value\n", a.c_str());
      return 2;
    }
    if (a == "--force") {
      force = true;
    } else if (a == "--out") {
      out_path = argv[++i];
    } else if (a == "--overlay") {
      overlay_dir = argv[++i];
    } else if (a == "--min-ncc") {
      if (!parse_double("--min-ncc", argv[++i], min_ncc)) {
        return 2;
      }
    } else if (a == "--sigma-motion") {
      if (!parse_double("--sigma-motion", argv[++i], sigma_motion) || sigma_motion <= 0.0) {
        return 2;
      }
    } else if (a == "--max-frames") {
      if (!parse_double("--max-frames", argv[++i], max_frames)) {
        return 2;
      }
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "cleanslam-track: unknown option '%s'\n", a.c_str());
      usage(stderr);
      return 2;
    } else if (dataset.empty()) {
      dataset = a;
    } else {
      std::fprintf(stderr, "cleanslam-track: unexpected argument '%s'\n", a.c_str());
      return 2;
    }
  }
  if (dataset.empty() || out_path.empty()) {
    usage(stderr);
    return 2;
  }

  auto loaded = cleanslam::readers::load_dataset(dataset);
  if (!loaded) {
    std::fprintf(stderr, "cleanslam-track: %s\n", loaded.error().c_str());
    return 1;
  }
  const cleanslam::readers::Dataset& ds = loaded.value();
  if (!ds.has_camera) {
    std::fprintf(stderr, "cleanslam-track: %s has no cam0/data.csv: nothing to track\n",
                 dataset.c_str());
    return 1;
  }
  const int width = ds.calibration.camera.width;
  const int height = ds.calibration.camera.height;
  if (width > cleanslam::hal::kImageWidth || height > cleanslam::hal::kImageHeight) {
    std::fprintf(stderr,
                 "cleanslam-track: %s/sensors.yaml: camera %dx%d exceeds the front end's capacity "
                 "%dx%d\n",
                 dataset.c_str(), width, height, cleanslam::hal::kImageWidth,
                 cleanslam::hal::kImageHeight);
    return 1;
  }
  if (const auto s = cleanslam::tools::prepare_output_file(out_path, force, {dataset}); !s) {
    std::fprintf(stderr, "cleanslam-track: %s\n", s.error().c_str());
    return 1;
  }
  if (!overlay_dir.empty()) {
    const cleanslam::tools::OwnedEntry ours = [](const std::string& name) {
      return name.size() == 10 && name.find_first_not_of("0123456789") == 6 &&
             name.compare(6, 4, ".png") == 0;
    };
    if (const auto s = cleanslam::tools::prepare_output_dir(overlay_dir, force, ours, {dataset});
        !s) {
      std::fprintf(stderr, "cleanslam-track: %s\n", s.error().c_str());
      return 1;
    }
  }
  std::FILE* out = std::fopen(out_path.c_str(), "w");
  if (out == nullptr) {
    std::fprintf(stderr, "cleanslam-track: cannot write %s: %s\n", out_path.c_str(),
                 std::strerror(errno));
    return 1;
  }
  std::fprintf(out, "#t_ns,track_id,u_px,v_px\n");

  fe::FramePipelineConfig cfg;
  cfg.width = width;
  cfg.height = height;
  cfg.tracker.min_ncc = static_cast<float>(min_ncc);
  fe::FramePipeline pipeline(cfg);
  tr::ImageOnlyEstimator::Config ecfg;
  ecfg.sigma_common_px = sigma_motion;
  tr::ImageOnlyEstimator estimator(ecfg);
  cleanslam::readers::GrayImage image;
  long frames = 0;
  long tracked = 0;
  long inliers = 0;
  long outliers = 0;
  long updates = 0;
  long deleted = 0;
  long initialized = 0;
  long rows = 0;
  const bool tty = isatty(STDERR_FILENO) != 0;
  const long total = max_frames >= 0.0 ? std::min(static_cast<long>(ds.camera.size()),
                                                  static_cast<long>(max_frames))
                                       : static_cast<long>(ds.camera.size());
  int shown = -1;
  const auto progress = [&](long done) {
    const int percent = total > 0 ? static_cast<int>(100 * done / total) : 100;
    const int step = tty ? percent : percent / 10 * 10;
    if (step == shown) {
      return;
    }
    shown = step;
    if (tty) {
      std::fprintf(stderr, "\rcleanslam-track: frame %ld of %ld, %3d%%", done, total, percent);
    } else {
      std::fprintf(stderr, "cleanslam-track: %3d %% (frame %ld of %ld)\n", step, done, total);
    }
    std::fflush(stderr);
  };
  progress(0);
  for (const cleanslam::readers::CameraIndexRow& row : ds.camera) {
    const std::string path = ds.image_path(row);
    if (max_frames >= 0.0 && static_cast<double>(frames) >= max_frames) {
      break;
    }
    if (const auto read = cleanslam::readers::read_gray_image(path, image); !read.ok()) {
      std::fprintf(stderr, "cleanslam-track: %s\n", read.error().c_str());
      std::fclose(out);
      return 1;
    }
    if (pipeline.begin_frame(image.view()) != fe::ImageCheck::kOk) {
      char msg[200];
      std::fprintf(stderr, "cleanslam-track: %s: %s (sensors.yaml)\n", path.c_str(),
                   pipeline.describe(msg, sizeof(msg)));
      std::fclose(out);
      return 1;
    }
    const fe::FrameReport& r = pipeline.finish(estimator);
    ++frames;
    tracked += r.tracked;
    inliers += r.inliers;
    outliers += r.outliers;
    updates += r.updated ? 1 : 0;
    deleted += r.deleted;
    initialized += r.initialized;
    if (r.jcbb.update) {
      for (int i = 0; i < pipeline.track_count(); ++i) {
        const fe::TrackRecord& t = pipeline.tracks()[i];
        if (t.result.found && t.inlier) {
          std::fprintf(out, "%lld,%lld,%.3f,%.3f\n", static_cast<long long>(row.t_ns),
                       static_cast<long long>(estimator.track_id(t.slot)), t.result.u_px,
                       t.result.v_px);
          ++rows;
        }
      }
    }
    for (int i = 0; i < pipeline.new_landmark_count(); ++i) {
      const fe::PixelObservation& o = pipeline.new_landmark(i);
      std::fprintf(out, "%lld,%lld,%.3f,%.3f\n", static_cast<long long>(row.t_ns),
                   static_cast<long long>(estimator.track_id(o.slot)), o.u_px, o.v_px);
      ++rows;
    }
    if (!overlay_dir.empty()) {
      tr::Overlay overlay(image.view());
      overlay.draw(pipeline, {frames - 1, static_cast<double>(row.t_ns) * 1e-9});
      char name[32];
      std::snprintf(name, sizeof(name), "/%06ld.png", frames - 1);
      std::string error;
      if (!overlay.write_png(overlay_dir + name, error)) {
        std::fprintf(stderr, "cleanslam-track: %s\n", error.c_str());
        std::fclose(out);
        return 1;
      }
    }
    estimator.end_frame();
    progress(frames);
  }
  if (tty) {
    std::fputc('\n', stderr);
  }
  std::fclose(out);
  std::fprintf(stderr,
               "cleanslam-track: %ld frames, %ld tracked (%.1f per frame), %ld inliers, %ld "
               "outliers, %ld frames updated, %ld landmarks initialized, %ld deleted, %ld rows "
               "written to %s\n",
               frames, tracked,
               frames > 0 ? static_cast<double>(tracked) / static_cast<double>(frames) : 0.0,
               inliers, outliers, updates, initialized, deleted, rows, out_path.c_str());
  return 0;
}
