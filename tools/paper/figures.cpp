#include "figures.hpp"

#include <limits>
#include <memory>
#include <string>

#include "cleanslam/paper_models/conventional_model.hpp"
#include "cleanslam/paper_models/inverse_depth_model.hpp"
#include "cleanslam/paper_models/multi_hypothesis_model.hpp"
#include "cleanslam/paper_models/proposed_model.hpp"
#include "cleanslam/slam_core/ekf.hpp"

namespace cleanslam::tools::paper {
namespace {

namespace m = paper_models;

constexpr double kCm = 0.01;  // m per cm
const m::Pinhole kCamera{280.0, 160.0, 120.0};

std::unique_ptr<slam_core::Ekf> make_ekf(const m::ProposedParams& params) {
  return std::make_unique<slam_core::Ekf>(m::pinhole_calibration(params.camera),
                                          m::proposed_config(params));
}

std::array<Eigen::Vector3d, m::kFig8Landmarks> fig8_landmarks(const m::KnownPose& pose) {
  std::array<Eigen::Vector3d, m::kFig8Landmarks> landmarks{};
  const auto directions = m::fig8_directions(kLandmarkSeed);
  for (std::size_t i = 0; i < m::kFig8Landmarks; ++i) {
    landmarks[i] = m::landmark_w(pose, directions[i], 1000.0 * kCm);
  }
  return landmarks;
}

}  // namespace

Table fig10(const Fig10Options& options) {
  constexpr double kAssumedDepth = 1000.0 * kCm;
  Table table;
  table.columns = {"true_depth_cm", "proposed_cm", "conventional_cm", "inverse_depth_cm",
                   "multi_hypothesis_cm"};
  const m::ProposedParams proposed{kCamera, 1e5 * kCm, 0.5 * kCm, kAssumedDepth, 1e12};
  const auto ekf = make_ekf(proposed);
  for (int depth_cm = 500; depth_cm <= 1500; depth_cm += 100) {
    const m::ComparisonSetup s = m::fig10_setup(options.motion, depth_cm * kCm);
    const auto error_cm = [&](m::LandmarkModel& model) {
      const m::OneStepResult r = m::one_step(model, kCamera, s.first, s.second, s.landmark);
      return r.status == m::ModelStatus::kOk ? r.error / kCm
                                             : std::numeric_limits<double>::quiet_NaN();
    };
    m::ProposedModel ours(*ekf);
    m::ConventionalModel conventional({kCamera, kAssumedDepth, 1e5 * kCm, 0.5 * kCm, 0.1});
    m::InverseDepthModel inverse_depth({kCamera, 1.0 / kAssumedDepth, 0.005 / kCm, 0.1, 0.1});
    m::MultiHypothesisModel multi_hypothesis(
        {kCamera, options.hypotheses, 100.0 * kCm, 3000.0 * kCm, 0.1, 1e-4});
    table.rows.push_back({static_cast<double>(depth_cm), error_cm(ours), error_cm(conventional),
                          error_cm(inverse_depth), error_cm(multi_hypothesis)});
  }
  return table;
}

Table fig8() {
  Table table;
  table.columns = {"ect_cm", "depth_diff_cm", "rms_cm"};
  const m::KnownPose first;
  const m::KnownPose second = m::moved_pose(first, m::Motion::kForward, 15.0 * kCm);
  const auto landmarks = fig8_landmarks(first);
  for (const double ect_cm : {200.0, 1000.0, 3000.0, 10000.0, 100000.0}) {
    for (const double diff_cm : {0.0, 1000.0, 2000.0, 3000.0}) {
      const m::ProposedParams params{kCamera, ect_cm * kCm, 0.5 * kCm, (1000.0 + diff_cm) * kCm,
                                     1e12};
      const auto ekf = make_ekf(params);
      const m::BatchResult r = m::proposed_one_step_batch(*ekf, kCamera, first, second, landmarks);
      table.rows.push_back({ect_cm, diff_cm, r.rms / kCm});
    }
  }
  return table;
}

Table fig7() {
  Table table;
  table.columns = {"landmark",   "true_x_cm",  "true_y_cm",  "true_z_cm",
                   "est_x_cm",   "est_y_cm",   "est_z_cm",   "cov_xx_cm2",
                   "cov_xy_cm2", "cov_yy_cm2", "robot_x_cm", "robot_y_cm"};
  const m::KnownPose first;
  const m::KnownPose second = m::moved_pose(first, m::Motion::kForward, 15.0 * kCm);
  const auto landmarks = fig8_landmarks(first);
  const m::ProposedParams params{kCamera, 1e4 * kCm, 0.5 * kCm, 2000.0 * kCm, 1e12};
  const auto ekf = make_ekf(params);
  const m::BatchResult r = m::proposed_one_step_batch(*ekf, kCamera, first, second, landmarks);
  for (std::size_t i = 0; i < m::kFig8Landmarks; ++i) {
    const Eigen::Vector3d t = landmarks[i] / kCm;
    const Eigen::Vector3d e = r.estimate[i] / kCm;
    const Eigen::Matrix3d c = r.covariance[i] / (kCm * kCm);
    table.rows.push_back({static_cast<double>(i), t.x(), t.y(), t.z(), e.x(), e.y(), e.z(), c(0, 0),
                          c(0, 1), c(1, 1), second.position_w.x() / kCm,
                          second.position_w.y() / kCm});
  }
  return table;
}

Table fig9(const Fig9Options& options) {
  Table table;
  table.columns = {"ect_cm", "rms_cm"};
  const m::KnownPose first;
  const auto landmarks = fig8_landmarks(first);
  const m::NoisyRunParams noisy{kCamera};
  constexpr double kAssumedDepth = 2000.0 * kCm;
  // Eq. 16 with the simulated tracking noise: eps_cn = eps_trk d / f at the assumed depth.
  const double eps_cn = noisy.pixel_noise_px * kAssumedDepth / kCamera.f_px;
  for (const double ect_cm :
       {200.0, 500.0, 1000.0, 2000.0, 3000.0, 5000.0, 10000.0, 30000.0, 100000.0}) {
    const auto ekf = make_ekf({kCamera, ect_cm * kCm, eps_cn, kAssumedDepth, 1e12});
    double sum = 0.0;
    int completed = 0;
    int rejected = 0;
    for (int run = 0; run < options.runs; ++run) {
      const m::NoisyRunResult r = m::proposed_noisy_run(
          *ekf, noisy, landmarks, options.seed + static_cast<std::uint32_t>(run));
      if (r.completed) {
        sum += r.rms;
        ++completed;
      }
      rejected += r.rejected;
    }
    if (completed < options.runs || rejected > 0) {
      table.notes.push_back("ect_cm " + std::to_string(static_cast<long>(ect_cm)) + ": " +
                            std::to_string(options.runs - completed) +
                            " runs left out (filter refused a step), " + std::to_string(rejected) +
                            " observations not fused");
    }
    table.rows.push_back({ect_cm, completed > 0 ? sum / static_cast<double>(completed) / kCm
                                                : std::numeric_limits<double>::quiet_NaN()});
  }
  return table;
}

}  // namespace cleanslam::tools::paper
