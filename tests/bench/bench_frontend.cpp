// The front end against OpenCV on synthetic warps of a procedural texture with known motion:
// Harris repeatability and time, tracking end-point error, track survival and time per frame.
// OpenCV is the peer here only; slam_core never links it.
//
//   bench_frontend --quality            quality tables only
//   bench_frontend [benchmark flags]    quality tables, then Google Benchmark timings
//   bench_frontend --callgrind=JOB      JOB in ours, opencv, ours-detect, opencv-detect: runs
//                                       kCallgrindFrames frames with callgrind instrumentation on
//                                       around the job only (valgrind --instr-atstart=no)
#include <benchmark/benchmark.h>
#include <valgrind/callgrind.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <random>
#include <string>
#include <vector>

#include "../unit/slam_core/frontend_fake_estimator.hpp"
#include "../unit/slam_core/frontend_synthetic.hpp"
#include "cleanslam/slam_core/frontend/frame_pipeline.hpp"
#include "cleanslam/slam_core/frontend/harris.hpp"
#include "cleanslam/slam_core/frontend/patch.hpp"
#include "cleanslam/slam_core/frontend/search_region.hpp"
#include "cleanslam/slam_core/frontend/tracker.hpp"

namespace fe = cleanslam::slam_core::frontend;
using cleanslam::test::GrayImage;
using cleanslam::test::render;
using cleanslam::test::Warp;

namespace {

constexpr int kW = 320;
constexpr int kH = 240;
constexpr int kLandmarks = 10;
constexpr int kCallgrindFrames = 20;
// OpenCV's pyramid depth for the seeded LK (the prediction is close; 2 levels absorb its error).
constexpr int kCvLevels = 2;

struct Case {
  const char* name;
  Warp warp;
  double pred_sigma_px;  // error of the EKF's predicted pixel, per axis
  double scale_error;    // relative error of the predicted depth ratio
};

std::vector<Case> cases() {
  std::vector<Case> c;
  Warp w;
  w.shift_x = 3.4;
  w.shift_y = -2.1;
  c.push_back({"shift_4px", w, 1.5, 0.0});
  w = Warp{};
  w.shift_x = 14.0;
  w.shift_y = 6.0;
  c.push_back({"shift_15px", w, 3.0, 0.0});
  w = Warp{};
  w.scale = 1.15;
  w.shift_x = 2.0;
  c.push_back({"forward_x1.15", w, 1.5, 0.03});
  w = Warp{};
  w.scale = 1.3;
  c.push_back({"forward_x1.3", w, 1.5, 0.05});
  w = Warp{};
  w.scale = 1.5;
  c.push_back({"forward_x1.5", w, 2.0, 0.05});
  w = Warp{};
  w.shift_x = -100.0;  // a 20 degree turn between frames at f = 280 px
  w.angle_rad = 0.02;
  c.push_back({"turn_100px", w, 3.0, 0.0});
  w = Warp{};
  w.shift_x = -196.0;  // 35 degrees: a 90 degree turn seen at about 1 Hz
  w.angle_rad = 0.03;
  c.push_back({"turn_196px", w, 4.0, 0.0});
  return c;
}

struct Landmark {
  double u0 = 0.0, v0 = 0.0;  // first sighting
  double tu = 0.0, tv = 0.0;  // truth now
  double pu = 0.0, pv = 0.0;  // prediction now
};

struct Sequence {
  GrayImage ref;
  GrayImage cur;
  std::vector<Landmark> lms;
  double predicted_scale = 1.0;
  double pred_sigma = 1.0;
};

Sequence make_sequence(const Case& c, std::uint32_t seed) {
  cleanslam::test::TextureOptions tex;
  tex.seed = seed;
  Sequence s;
  s.ref = render(Warp{}, kW, kH, 1.0, 0.0, tex);
  s.cur = render(c.warp, kW, kH, 1.0, 0.0, tex);
  s.pred_sigma = c.pred_sigma_px;
  s.predicted_scale = c.warp.scale * (1.0 + c.scale_error);
  fe::HarrisDetector det;
  det.detect(s.ref.view(), kW, kH);
  std::mt19937 rng(seed * 7919U + 1U);
  std::normal_distribution<double> noise(0.0, c.pred_sigma_px);
  for (int i = 0; i < det.corner_count() && static_cast<int>(s.lms.size()) < kLandmarks; ++i) {
    Landmark lm;
    lm.u0 = det.corners()[i].x;
    lm.v0 = det.corners()[i].y;
    if (lm.u0 < 17 || lm.v0 < 17 || lm.u0 > kW - 18 || lm.v0 > kH - 18) {
      continue;
    }
    c.warp.apply(lm.u0, lm.v0, lm.tu, lm.tv);
    if (lm.tu < 20 || lm.tv < 20 || lm.tu > kW - 21 || lm.tv > kH - 21) {
      continue;
    }
    lm.pu = lm.tu + noise(rng);
    lm.pv = lm.tv + noise(rng);
    s.lms.push_back(lm);
  }
  return s;
}

struct TrackOut {
  bool kept = false;
  double u = 0.0, v = 0.0;
};

struct Ours {
  fe::HarrisDetector det;
  fe::PatchStore store;
  fe::Tracker tracker;
  const Sequence* seq = nullptr;
  std::vector<TrackOut> out;

  explicit Ours(const Sequence& s) : seq(&s), out(s.lms.size()) {
    for (std::size_t i = 0; i < s.lms.size(); ++i) {
      store.capture(static_cast<int>(i), s.ref.view(), s.lms[i].u0, s.lms[i].v0, 2.0);
    }
  }
};

__attribute__((noinline)) void ours_detect(Ours& o) {
  o.det.detect(o.seq->cur.view(), kW, kH);
}

__attribute__((noinline)) void ours_frame(Ours& o) {
  o.det.detect(o.seq->cur.view(), kW, kH);
  const double var = o.seq->pred_sigma * o.seq->pred_sigma + 1.0;
  for (std::size_t i = 0; i < o.seq->lms.size(); ++i) {
    const Landmark& lm = o.seq->lms[i];
    fe::PixelPrediction pred;
    pred.uv = {lm.pu, lm.pv};
    pred.S = Eigen::Matrix2d::Identity() * var;
    pred.depth_m = 2.0 / o.seq->predicted_scale;
    pred.in_front = true;
    const fe::SearchRegion region = fe::make_search_region(pred, kW, kH);
    const fe::LandmarkPatch* patch = o.store.get(static_cast<int>(i));
    fe::PatchTemplate tmpl;
    TrackOut& t = o.out[i];
    t.kept = false;
    if (patch == nullptr ||
        !fe::make_template(*patch, fe::predicted_patch_scale(patch->first_depth_m, pred.depth_m),
                           3.0F, tmpl)) {
      continue;
    }
    const fe::TrackResult r =
        o.tracker.track(o.seq->cur.view(), tmpl, region, o.det.corners(), o.det.corner_count());
    t.kept = r.found;
    t.u = r.u_px;
    t.v = r.v_px;
  }
}

struct Cv {
  cv::Mat ref;
  cv::Mat cur;
  std::vector<cv::Mat> ref_pyr;
  std::vector<cv::Mat> cur_pyr;
  std::vector<cv::Point2f> prev_pts;
  std::vector<cv::Point2f> next_pts;
  std::vector<cv::Point2f> seeds;
  std::vector<cv::Point2f> corners;
  std::vector<unsigned char> status;
  std::vector<float> err;
  const Sequence* seq = nullptr;

  explicit Cv(const Sequence& s)
      : ref(kH, kW, CV_8UC1, const_cast<std::uint8_t*>(s.ref.pixels.data())),
        cur(kH, kW, CV_8UC1, const_cast<std::uint8_t*>(s.cur.pixels.data())),
        seq(&s) {
    cv::buildOpticalFlowPyramid(ref, ref_pyr, cv::Size(15, 15), kCvLevels);
    for (const Landmark& lm : s.lms) {
      prev_pts.emplace_back(static_cast<float>(lm.u0), static_cast<float>(lm.v0));
      seeds.emplace_back(static_cast<float>(lm.pu), static_cast<float>(lm.pv));
    }
    corners.reserve(256);
  }
};

void cv_detect_into(Cv& c, int max_corners) {
  cv::goodFeaturesToTrack(c.cur, c.corners, max_corners, 0.01, 5.0, cv::noArray(), 3, true, 0.04);
}

__attribute__((noinline)) void opencv_detect(Cv& c) {
  cv_detect_into(c, 256);
}

__attribute__((noinline)) void opencv_frame(Cv& c) {
  cv_detect_into(c, 256);
  c.next_pts = c.seeds;
  cv::buildOpticalFlowPyramid(c.cur, c.cur_pyr, cv::Size(15, 15), kCvLevels);
  cv::calcOpticalFlowPyrLK(
      c.ref_pyr, c.cur_pyr, c.prev_pts, c.next_pts, c.status, c.err, cv::Size(15, 15), kCvLevels,
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 0.01),
      cv::OPTFLOW_USE_INITIAL_FLOW);
}

struct Quality {
  int tracks = 0;
  int kept = 0;
  int correct = 0;  // kept and within 1 px of the truth
  double epe_sum = 0.0;
  double epe_max = 0.0;
  std::vector<double> epes;
  void add(bool kept_track, double epe) {
    ++tracks;
    if (!kept_track) {
      return;
    }
    ++kept;
    correct += epe < 1.0 ? 1 : 0;
    epe_sum += epe;
    epe_max = std::max(epe_max, epe);
    epes.push_back(epe);
  }
  [[nodiscard]] double median() {
    if (epes.empty()) {
      return 0.0;
    }
    std::sort(epes.begin(), epes.end());
    return epes[epes.size() / 2];
  }
};

double repeatability(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b,
                     const Warp& w) {
  int inside = 0;
  int hit = 0;
  for (const cv::Point2f& p : a) {
    double u = 0.0;
    double v = 0.0;
    w.apply(static_cast<double>(p.x), static_cast<double>(p.y), u, v);
    if (u < 10 || v < 10 || u > kW - 11 || v > kH - 11) {
      continue;
    }
    ++inside;
    for (const cv::Point2f& q : b) {
      if (std::hypot(static_cast<double>(q.x) - u, static_cast<double>(q.y) - v) < 1.5) {
        ++hit;
        break;
      }
    }
  }
  return inside == 0 ? 0.0 : static_cast<double>(hit) / inside;
}

std::vector<cv::Point2f> ours_points(const GrayImage& img, int max_corners) {
  fe::HarrisConfig cfg;
  cfg.max_corners = max_corners;
  fe::HarrisDetector det(cfg);
  det.detect(img.view(), kW, kH);
  std::vector<cv::Point2f> pts;
  for (int i = 0; i < det.corner_count(); ++i) {
    pts.emplace_back(static_cast<float>(det.corners()[i].x),
                     static_cast<float>(det.corners()[i].y));
  }
  return pts;
}

std::vector<cv::Point2f> cv_points(const GrayImage& img, int max_corners) {
  const cv::Mat m(kH, kW, CV_8UC1, const_cast<std::uint8_t*>(img.pixels.data()));
  std::vector<cv::Point2f> pts;
  cv::goodFeaturesToTrack(m, pts, max_corners, 0.01, 5.0, cv::noArray(), 3, true, 0.04);
  return pts;
}

void print_quality() {
  constexpr int kSeeds = 8;
  std::printf("# Tracking quality, %d landmarks x %d textures per case (EPE in px; kept = the\n",
              kLandmarks, kSeeds);
  std::printf("# tracker reports a match; correct = kept and EPE < 1 px; gate = landmarks whose\n");
  std::printf("# true pixel lies outside their own 99%% search gate, which ours cannot keep)\n");
  std::printf("%-14s | %-28s | %-28s | %s\n", "case", "ours kept/correct  EPE med/max",
              "opencv kept/correct EPE med/max", "gate");
  for (const Case& c : cases()) {
    Quality qo;
    Quality qc;
    int outside_gate = 0;
    for (int s = 1; s <= kSeeds; ++s) {
      const Sequence seq = make_sequence(c, static_cast<std::uint32_t>(s));
      Ours o(seq);
      ours_frame(o);
      Cv cvx(seq);
      opencv_frame(cvx);
      for (std::size_t i = 0; i < seq.lms.size(); ++i) {
        const Landmark& lm = seq.lms[i];
        const double var = seq.pred_sigma * seq.pred_sigma + 1.0;
        const double du = lm.tu - lm.pu;
        const double dv = lm.tv - lm.pv;
        outside_gate += (du * du + dv * dv) / var > fe::SearchRegionConfig{}.gate_chi2 ? 1 : 0;
        qo.add(o.out[i].kept, std::hypot(o.out[i].u - lm.tu, o.out[i].v - lm.tv));
        qc.add(cvx.status[i] != 0, std::hypot(static_cast<double>(cvx.next_pts[i].x) - lm.tu,
                                              static_cast<double>(cvx.next_pts[i].y) - lm.tv));
      }
    }
    std::printf("%-14s | %5.1f%% %5.1f%%  %6.3f %7.3f | %5.1f%% %5.1f%%  %6.3f %7.3f | %d/%d\n",
                c.name, 100.0 * qo.kept / qo.tracks, 100.0 * qo.correct / qo.tracks, qo.median(),
                qo.epe_max, 100.0 * qc.kept / qc.tracks, 100.0 * qc.correct / qc.tracks,
                qc.median(), qc.epe_max, outside_gate, qo.tracks);
  }
  std::printf("\n# Harris repeatability (top 100 corners, a reference corner found again within\n");
  std::printf("# 1.5 px of its true position), mean over %d textures\n", kSeeds);
  std::printf("%-14s | %8s | %8s\n", "case", "ours", "opencv");
  for (const Case& c : cases()) {
    double ro = 0.0;
    double rc = 0.0;
    for (int s = 1; s <= kSeeds; ++s) {
      cleanslam::test::TextureOptions tex;
      tex.seed = static_cast<std::uint32_t>(s);
      const GrayImage ref = render(Warp{}, kW, kH, 1.0, 0.0, tex);
      const GrayImage cur = render(c.warp, kW, kH, 1.0, 0.0, tex);
      ro += repeatability(ours_points(ref, 100), ours_points(cur, 100), c.warp);
      rc += repeatability(cv_points(ref, 100), cv_points(cur, 100), c.warp);
    }
    std::printf("%-14s | %7.1f%% | %7.1f%%\n", c.name, 100.0 * ro / kSeeds, 100.0 * rc / kSeeds);
  }
  std::printf("\n");
  std::fflush(stdout);
}

double thread_cpu_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
}

// The resumable pipeline (default step sizes) on a forward-then-turn sequence with a fake
// estimator: the longest step of each stage, i.e. what the cooperative loop must budget for.
void print_pipeline_steps() {
  constexpr int kFrames = 16;
  std::vector<GrayImage> frames;
  std::vector<Warp> warps;
  Warp w;
  for (int k = 0; k < kFrames; ++k) {
    if (k < 8) {
      w.scale *= 1.05;
    } else {
      w.shift_x -= 25.0;
    }
    warps.push_back(w);
    frames.push_back(render(w));
  }
  fe::FramePipeline pipe;
  cleanslam::test::FakeEstimator est;
  constexpr int kStages = static_cast<int>(fe::FrameStage::kDone) + 1;
  std::array<double, kStages> worst{};
  std::array<long, kStages> count{};
  double worst_frame = 0.0;
  double total = 0.0;
  int tracked = 0;
  for (int rep = 0; rep < 5; ++rep) {
    for (int k = 0; k < kFrames; ++k) {
      est.belief = warps[static_cast<std::size_t>(k)];
      est.truth = warps[static_cast<std::size_t>(k)];
      pipe.begin_frame(frames[static_cast<std::size_t>(k)].view());
      double frame_us = 0.0;
      bool more = true;
      while (more) {
        const auto stage = static_cast<std::size_t>(pipe.stage());
        const double t0 = thread_cpu_us();
        more = pipe.step(est);
        const double us = thread_cpu_us() - t0;
        worst[stage] = std::max(worst[stage], us);
        ++count[stage];
        frame_us += us;
      }
      tracked += pipe.report().tracked;
      worst_frame = std::max(worst_frame, frame_us);
      total += frame_us;
    }
  }
  const char* names[kStages] = {"idle",   "detect", "predict",    "track", "associate",
                                "update", "manage", "initialize", "done"};
  std::printf(
      "# Frame pipeline, default step sizes, %d frames x 5 (fake estimator): longest step\n",
      kFrames);
  std::printf("# per stage (us, thread CPU time) and steps per frame\n");
  for (int i = 1; i < kStages - 1; ++i) {
    std::printf("%-11s %8.1f us  %5.1f steps/frame\n", names[i], worst[static_cast<std::size_t>(i)],
                static_cast<double>(count[static_cast<std::size_t>(i)]) / (5.0 * kFrames));
  }
  std::printf("frame total: mean %.1f us, worst %.1f us; %.1f landmarks tracked per frame\n\n",
              total / (5.0 * kFrames), worst_frame, tracked / (5.0 * kFrames));
  std::fflush(stdout);
}

int run_callgrind(const std::string& job) {
  const Sequence seq = make_sequence(cases()[0], 1);
  Ours o(seq);
  Cv c(seq);
  // Warm up outside the instrumented region (first-call allocations, lazy init).
  ours_frame(o);
  opencv_frame(c);
  for (int i = 0; i < kCallgrindFrames; ++i) {
    CALLGRIND_START_INSTRUMENTATION;
    if (job == "ours") {
      ours_frame(o);
    } else if (job == "opencv") {
      opencv_frame(c);
    } else if (job == "ours-detect") {
      ours_detect(o);
    } else if (job == "opencv-detect") {
      opencv_detect(c);
    } else {
      std::fprintf(stderr, "bench_frontend: unknown --callgrind job '%s'\n", job.c_str());
      return 2;
    }
    CALLGRIND_STOP_INSTRUMENTATION;
  }
  std::printf("callgrind job %s: %d frames\n", job.c_str(), kCallgrindFrames);
  return 0;
}

void register_benchmarks() {
  static std::vector<std::unique_ptr<Sequence>> seqs;
  for (const Case& c : cases()) {
    seqs.push_back(std::make_unique<Sequence>(make_sequence(c, 1)));
    const Sequence* s = seqs.back().get();
    const std::string name = c.name;
    benchmark::RegisterBenchmark(("ours/detect_track/" + name).c_str(), [s](benchmark::State& st) {
      Ours o(*s);
      for (auto _ : st) {
        ours_frame(o);
        benchmark::DoNotOptimize(o.out.data());
      }
    })->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("opencv/detect_track/" + name).c_str(),
                                 [s](benchmark::State& st) {
                                   Cv c2(*s);
                                   for (auto _ : st) {
                                     opencv_frame(c2);
                                     benchmark::DoNotOptimize(c2.next_pts.data());
                                   }
                                 })
        ->Unit(benchmark::kMicrosecond);
  }
  const Sequence* s0 = seqs.front().get();
  benchmark::RegisterBenchmark("ours/detect/shift_4px", [s0](benchmark::State& st) {
    Ours o(*s0);
    for (auto _ : st) {
      ours_detect(o);
      benchmark::DoNotOptimize(o.det.corners());
    }
  })->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("opencv/detect/shift_4px", [s0](benchmark::State& st) {
    Cv c(*s0);
    for (auto _ : st) {
      opencv_detect(c);
      benchmark::DoNotOptimize(c.corners.data());
    }
  })->Unit(benchmark::kMicrosecond);
}

}  // namespace

int main(int argc, char** argv) {
  // The robot's loop is single-threaded; so is the comparison.
  cv::setNumThreads(1);
  bool quality_only = false;
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    if (std::strncmp(argv[i], "--callgrind=", 12) == 0) {
      return run_callgrind(argv[i] + 12);
    }
    if (std::strcmp(argv[i], "--quality") == 0) {
      quality_only = true;
      continue;
    }
    rest.push_back(argv[i]);
  }
  print_quality();
  print_pipeline_steps();
  if (quality_only) {
    return 0;
  }
  int n = static_cast<int>(rest.size());
  benchmark::Initialize(&n, rest.data());
  register_benchmarks();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
