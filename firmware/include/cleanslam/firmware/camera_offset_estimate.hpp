#pragma once

#include <array>
#include <cstdint>

#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/log_format.hpp"
#include "cleanslam/hal/samples.hpp"

namespace cleanslam::firmware {

// The camera-to-odometry time offset the data suggest, from the image motion of tracked points
// against the gyro's turn: a point seen in two frames moved in the image by what the camera turned
// between the two capture instants (plus the parallax of the travel, left as noise). For each
// candidate offset d the turn is integrated from the gyro between the frames' stamps plus d; the
// candidate that explains the points' motion best (least squares, each pair's error capped
// against mismatched points) is the offset the data suggest. Independent of the filter's
// estimate; fixed memory. Fed by the loop as one of its update and gyro sinks.
class CameraOffsetEstimate final : public UpdateSink, public GyroSink {
 public:
  struct Result {
    bool measurable = false;  // enough turning between frames to tell the candidates apart
    double suggested_s = 0.0;
    double std_s = 0.0;
    double configured_s = 0.0;
    std::uint64_t pairs = 0;  // a point seen in two consecutive frames
  };

  static constexpr double kRangeS = 1.0;  // candidates: configured offset +- this
  static constexpr int kCandidates = 201;
  static constexpr double kMaxStdS = 0.05;  // measurable below this std. dev.
  static constexpr std::uint64_t kMinPairs = 20;
  // A suggested offset further than this (and three std. dev.) from the configured one is warned.
  static constexpr double kWarnS = 0.05;

  CameraOffsetEstimate() = default;
  explicit CameraOffsetEstimate(const hal::CameraCalibration& camera);

  void gyro(const hal::GyroSample& s) override;
  void update(const hal::log::UpdateRecord& r) override;
  [[nodiscard]] Result result() const;

 private:
  struct Turn {  // the body's turn integrated from the first sample, at a sample's time
    hal::TimeNs t_ns = 0;
    std::array<double, 3> angle{};
    std::array<double, 3> rate{};
    std::uint64_t span = 0;  // counts the gyro's gaps: a turn across one is unknown
  };
  struct Point {
    std::int64_t track = -1;
    hal::TimeNs t_ns = 0;
    double u = 0.0;
    double v = 0.0;
  };
  struct Pair {
    Point a;
    Point b;
  };
  [[nodiscard]] const Turn& turn(int k) const;  // k = 0: the oldest kept sample
  // The turn at t_ns, from the samples k and k + 1 around it; k is where to start looking (a
  // later t_ns than the last call's walks on from there, -1 bisects) and is updated.
  bool turn_at(hal::TimeNs t_ns, int& k, std::array<double, 3>& angle, std::uint64_t& span) const;
  // Pairs wait until the gyro has passed the later frame's latest candidate instant.
  void evaluate_ready_pairs();
  void evaluate(const Pair& p);

  static constexpr int kTurns = 1024;   // 10 s of a 100 Hz gyro
  static constexpr int kPoints = 64;    // points of the last frame
  static constexpr int kPending = 128;  // pairs waiting for the gyro
  static constexpr int kPairsPerGyroSample = 4;
  static constexpr hal::TimeNs kMaxFrameGapNs = 1'500'000'000;
  static constexpr double kMaxPairErrorPx = 10.0;

  bool valid_ = false;
  double fx_ = 0.0, fy_ = 0.0, cx_ = 0.0, cy_ = 0.0;
  std::array<double, 9> R_cam_body_{};  // body vector to camera frame (row-major)
  double configured_s_ = 0.0;
  std::array<Turn, kTurns> turns_{};
  int newest_ = -1;
  int turn_count_ = 0;
  std::array<Point, kPoints> last_{};  // the previous frame's points
  std::array<Point, kPoints> current_{};
  int last_count_ = 0;
  int current_count_ = 0;
  hal::TimeNs current_t_ns_ = -1;
  std::array<Pair, kPending> pending_{};
  int pending_first_ = 0;
  int pending_count_ = 0;
  std::array<double, kCandidates> sse_{};
  std::uint64_t pairs_ = 0;
};

}  // namespace cleanslam::firmware
