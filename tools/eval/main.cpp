// cleanslam-eval --gt DATASET/groundtruth.csv --est FILE.tum [--align none|se2|se3] [--json]
// Trajectory metrics of an estimate against ground truth; covariances from FILE.tum.cov when it
// exists (format: evaluation/include/cleanslam/evaluation/evaluation.hpp).
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include "cleanslam/evaluation/evaluation.hpp"
#include "cleanslam/readers/dataset.hpp"

namespace {

void usage(std::FILE* out) {
  std::fprintf(out,
               "usage: cleanslam-eval --gt DATASET/groundtruth.csv --est FILE.tum "
               "[--align none|se2|se3] [--json] [--cov FILE]\n"
               "  --align  none (default): both trajectories relative to their first pose;\n"
               "           se2 / se3: least-squares rigid alignment without scale\n"
               "  --json   one JSON object on stdout instead of text\n"
               "  --cov    covariance side file (default FILE.tum.cov when it exists): per line\n"
               "           t and the 3x3 (9 numbers) or 6x6 (36) covariance, row-major\n");
}

}  // namespace

int main(int argc, char** argv) {
  namespace ev = cleanslam::evaluation;
  std::string gt_path, est_path, cov_path;
  ev::Alignment align = ev::Alignment::kNone;
  std::string align_name = "none";
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    auto value = [&](std::string& out) {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "cleanslam-eval: %s needs a value\n", argv[i]);
        return false;
      }
      out = argv[++i];
      return true;
    };
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--gt") {
      if (!value(gt_path)) {
        return 2;
      }
    } else if (a == "--est") {
      if (!value(est_path)) {
        return 2;
      }
    } else if (a == "--cov") {
      if (!value(cov_path)) {
        return 2;
      }
    } else if (a == "--align") {
      if (!value(align_name)) {
        return 2;
      }
      if (align_name == "none") {
        align = ev::Alignment::kNone;
      } else if (align_name == "se2") {
        align = ev::Alignment::kSe2;
      } else if (align_name == "se3") {
        align = ev::Alignment::kSe3;
      } else {
        std::fprintf(stderr, "cleanslam-eval: --align: expected none, se2 or se3, got \"%s\"\n",
                     align_name.c_str());
        return 2;
      }
    } else if (a == "--json") {
      json = true;
    } else {
      std::fprintf(stderr, "cleanslam-eval: unexpected argument %s\n", argv[i]);
      usage(stderr);
      return 2;
    }
  }
  if (gt_path.empty() || est_path.empty()) {
    usage(stderr);
    return 2;
  }
  auto gt = cleanslam::readers::read_groundtruth_csv(gt_path);
  if (!gt.ok()) {
    std::fprintf(stderr, "cleanslam-eval: %s\n", gt.error().c_str());
    return 1;
  }
  auto est = ev::read_tum(est_path);
  if (!est.ok()) {
    std::fprintf(stderr, "cleanslam-eval: %s\n", est.error().c_str());
    return 1;
  }
  std::error_code ec;
  if (cov_path.empty() && std::filesystem::exists(est_path + ".cov", ec)) {
    cov_path = est_path + ".cov";
  }
  if (!cov_path.empty()) {
    auto s = ev::read_covariances(cov_path, *est);
    if (!s) {
      std::fprintf(stderr, "cleanslam-eval: %s\n", s.error().c_str());
      return 1;
    }
  }
  auto m = ev::evaluate(*gt, *est, align);
  if (!m.ok()) {
    std::fprintf(stderr, "cleanslam-eval: %s\n", m.error().c_str());
    return 1;
  }
  if (json) {
    std::printf("%s\n", ev::to_json(*m, align).c_str());
  } else {
    std::printf("%s", ev::to_text(*m, align).c_str());
  }
  return 0;
}
