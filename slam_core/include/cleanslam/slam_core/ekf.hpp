#pragma once

#include <array>
#include <cstdint>
#include <span>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/hal/pose.hpp"
#include "cleanslam/hal/time.hpp"
#include "cleanslam/slam_core/camera_model.hpp"
#include "cleanslam/slam_core/ekf_config.hpp"
#include "cleanslam/slam_core/geometry.hpp"
#include "cleanslam/slam_core/odometry_increment.hpp"
#include "cleanslam/slam_core/pose_solve.hpp"
#include "cleanslam/slam_core/update_status.hpp"

// The paper's EKF (eq. 1-27, 39-45): camera pose plus a fixed pool of landmark slots; slot i
// occupies state rows 6+3i..6+3i+2. Unused slots' rows and columns of P stay zero. All storage
// (about 2 MB) is allocated by the constructor; no later call allocates.
namespace cleanslam::slam_core {

struct Observation {
  int slot = -1;
  double u_px = 0.0;  // distorted pixel
  double v_px = 0.0;
};

struct PixelPrediction {
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // distorted pixel
  Eigen::Matrix2d S = Eigen::Matrix2d::Zero();   // H_pix P H_pix^T + R_pix
  double depth_m = 0.0;                          // along the optical axis
  bool in_front = false;
};

struct EkfCounters {
  RejectionCounters rejections;  // update and initialization, by reason
  std::uint64_t predictions = 0;
  std::uint64_t predictions_rejected = 0;
  std::uint64_t updates_applied = 0;
  std::uint64_t landmarks_initialized = 0;
  std::uint64_t landmarks_replaced = 0;
  std::uint64_t landmarks_deleted = 0;
  std::uint64_t consider_observations = 0;  // fused with the consider (Schmidt) gain
  std::uint64_t landmarks_merged = 0;
  std::uint64_t merges_gated = 0;
  std::uint64_t pose_solves = 0;  // updates linearized at a solved pose
};

class Ekf {
 public:
  static constexpr int kMaxStateDim = hal::kMaxStateDim;
  static constexpr int kMaxMeasDim = 3 * hal::kMaxObservationsPerFrame;
  // Allocated by the constructor for the configured pool (6 + 3 max_landmarks rows, at most
  // kMaxStateDim) and never resized; calls work on blocks.
  using StateVector = Eigen::VectorXd;
  using StateMatrix = Eigen::MatrixXd;

  Ekf(const hal::Calibration& calibration, const EkfConfig& config);
  Ekf(const Ekf&) = delete;
  Ekf& operator=(const Ekf&) = delete;

  // The range the filter represents: no state entry beyond kMaxAbsState (m, rad) and
  // no variance beyond kMaxVariance; a call whose result would leave it is refused. Far
  // beyond any robot's workspace, they keep every product of the state's and P's entries, and
  // their rounding, finite (inputs of 1e150 and beyond, found by fuzzing, overflowed them).
  static constexpr double kMaxAbsState = 1e6;
  static constexpr double kMaxVariance = 1e12;
  // An angle of the pose with a standard deviation of 10 rad is not known at all, and nothing
  // linearized about it means anything: the pose's angles have no variance beyond this. A yaw
  // variance near kMaxVariance, taken back by a merge, left P indefinite beyond its rounding in
  // the rows that a landmark initialized later multiplied by its lever arm (found by fuzzing).
  static constexpr double kMaxAngleVariance = 100.0;

  // Camera pose (x, y, z, roll, pitch, yaw) and its covariance; the map is emptied. False, with
  // nothing changed, for a pose or covariance not finite, out of range or not positive
  // semi-definite.
  [[nodiscard]] bool reset(const Vector6d& camera_pose, const Matrix6d& P0);

  // Eq. 3-9.
  PredictStatus predict(const OdometryIncrement& u);

  // Eq. 39-45. Returns the slot, or -1 (reason counted). A full pool replaces the least useful
  // landmark: the one fused least recently, then the one fused fewest times.
  int initialize_landmark(double u_px, double v_px);
  // The same at a depth known from elsewhere, with std. dev. eps_ct_m along the ray.
  int initialize_landmark(double u_px, double v_px, double depth_m, double eps_ct_m);

  void delete_landmark(int slot);

  // The camera pose estimate moved to camera_pose, the pose found again against the map after it
  // was lost (Relocalizer): x, y and yaw take planar_cov (over x, y, yaw) and no correlation with
  // the rest of the state (what the lost estimate knew of them is void); height, roll, pitch and
  // the landmarks are unchanged. False, with nothing changed, for a pose or covariance not finite,
  // a covariance not positive definite, or while an update is pending.
  bool relocate(const Vector6d& camera_pose, const Eigen::Matrix3d& planar_cov);

  // Two slots that hold the same point (a landmark mapped again after the pose was lost, and its
  // earlier map entry): the linear update with the constraint y_keep - y_drop = 0 (std. dev.
  // merge_std_m per axis, and never below 3e-5 of the difference's largest std. dev.), gated at
  // gate_chi2 on its 3 dof (none when not above 0), then drop is deleted
  // (EkfConfig::merge_considers_kept: keep is a considered state). kFused when merged; kGate,
  // kNotPositiveDefinite, kOutOfRange or kInvalidSlot (nothing changed) otherwise.
  ObservationResult merge_landmarks(int keep, int drop, double gate_chi2,
                                    double merge_std_m = 0.01);
  // The last merge's test ratio (its innovation's squared Mahalanobis norm, 3 dof), gated or not;
  // -1 when it did not get that far.
  [[nodiscard]] double last_merge_test_ratio() const { return merge_test_ratio_; }

  // Per-observation gates (3-D and pixel), then one batch Joseph-form update of the survivors (eq.
  // 25-27). With a step budget (set_update_step) the update may return still pending: the status
  // is final once update_pending() is false.
  const UpdateStatus& update(const Observation* obs, int count);
  [[nodiscard]] const UpdateStatus& last_update() const { return status_; }

  // Bounded work per call for the batch update: about this much work per update() or
  // continue_update() call, in units of about one instruction (at least one piece: a few gain rows
  // or a covariance column); 0, the default, runs every update to completion at once. The chunked
  // result equals the one-shot one.
  void set_update_step(std::int64_t work);
  [[nodiscard]] std::int64_t update_step() const { return step_budget_; }
  // An update is under way: the gain rows, then the covariance columns, over several calls. Its
  // state correction is applied as soon as the gain is complete; while pending, pose() and
  // pose_covariance() are already the posterior's once the covariance columns have begun.
  [[nodiscard]] bool update_pending() const { return phase_ != UpdatePhase::kNone; }
  // One bounded step of a pending update; true when it is finished (last_update() final).
  bool continue_update();
  // The rest of a pending update at once. predict, update, initialize_landmark and delete_landmark
  // call it first, so a caller that does not wait for the pending update still gets the one-shot
  // result.
  void finish_update();

  // Predicted distorted pixel of a landmark with its 2x2 covariance (exactly symmetric), for
  // search regions; false for an unused slot, a landmark behind the camera or a projection that
  // overflows.
  bool predict_pixel(int slot, PixelPrediction& out) const;

  // Stacked pixel innovations (2m) and their joint covariance (2m x 2m, column-major) for JCBB,
  // m = obs.size(). Returns m, or -1 when an observation has an unused slot,
  // a bad pixel or a landmark behind the camera, m exceeds hal::kMaxObservationsPerFrame, or nu or
  // S is too small; -1 also when the result is not finite.
  int joint_pixel_innovation(std::span<const Observation> obs, std::span<double> nu,
                             std::span<double> S) const;

  [[nodiscard]] Vector6d camera_pose() const { return x_.head<6>(); }
  [[nodiscard]] Matrix6d pose_covariance() const { return P_.topLeftCorner<6, 6>(); }
  [[nodiscard]] bool slot_used(int slot) const;
  // Std. dev. of the landmark's depth relative to the camera, along the camera-landmark line,
  // divided by that depth; -1 for an unused slot.
  [[nodiscard]] double relative_depth_std(int slot) const;
  // The consider update applies to it (EkfConfig::consider_young_landmarks).
  [[nodiscard]] bool young(int slot) const;
  [[nodiscard]] Eigen::Vector3d landmark(int slot) const;
  [[nodiscard]] Eigen::Matrix3d landmark_covariance(int slot) const;
  [[nodiscard]] const std::array<bool, hal::kMaxLandmarks>& used_mask() const { return used_; }
  [[nodiscard]] int landmark_count() const { return landmark_count_; }
  // Rows of the state in use: 6 + 3 * (highest used slot + 1).
  [[nodiscard]] int active_dim() const { return active_dim_; }
  [[nodiscard]] const StateVector& state() const { return x_; }
  [[nodiscard]] const StateMatrix& covariance() const { return P_; }
  [[nodiscard]] const EkfCounters& counters() const { return counters_; }
  [[nodiscard]] const CameraModel& camera() const { return camera_; }
  [[nodiscard]] const EkfConfig& config() const { return config_; }

  // Body pose (through T_body_c) with its covariance, landmark count filled in.
  [[nodiscard]] hal::PoseEstimate body_pose_estimate(hal::TimeNs t_ns) const;

 private:
  struct SlotInfo {
    std::uint64_t last_fused = 0;  // update counter at the last fusion or initialization
    std::uint32_t fused = 0;
  };
  static int row_of(int slot) { return hal::kPoseDim + hal::kLandmarkDim * slot; }
  // reset() without its checks: P0s symmetric, the pose and P0s inside the range.
  void start(const Vector6d& camera_pose, const Matrix6d& P0s);
  [[nodiscard]] bool valid_used_slot(int slot) const;
  // The PSD guard of an update for row i's posterior variance d: above min_variance for the pose
  // and used landmarks, anything for an unused row.
  [[nodiscard]] bool posterior_variance_ok(int i, double d) const;
  // Rows [0, n) of x + dx inside kMaxAbsState, and finite.
  [[nodiscard]] bool state_in_range(int n, const Eigen::Ref<const Eigen::VectorXd>& dx) const;
  // Unit vector from the camera to the landmark and its length; false for an unused slot.
  bool ray_to(int slot, Eigen::Vector3d& u, double& depth) const;
  int take_slot();
  void recompute_active_dim();
  ObservationResult measure(const Observation& o, Eigen::Vector3d& z, Eigen::Matrix3d& R,
                            Eigen::Vector3d& h, Eigen::Matrix<double, 3, 6>& Hp,
                            Eigen::Matrix3d& Hl) const;
  bool pixel_jacobian(int slot, Eigen::Vector2d& uv, Eigen::Matrix<double, 2, 6>& Jp,
                      Eigen::Matrix<double, 2, 3>& Jl, double& depth) const;
  // offset: the linearization pose minus the prior's; the innovation is the iterated EKF's.
  ObservationResult pixel_gate(const Observation& o, const Vector6d& offset,
                               ObservationStatus& st) const;
  // EkfConfig::solve_pose_beyond_linear_range: true, with the pose to linearize the update at,
  // when the prior's pose is outside the linear range of a sighting of an established (not young)
  // landmark and the solve converged.
  bool linearization_pose(const Observation* obs, int count, Vector6d& pose);
  [[nodiscard]] SightingNoise sighting_noise() const;
  enum class UpdatePhase : std::uint8_t { kNone, kGain, kGainRows, kCovariance };
  // One step of the pending update within the budget (all of it when the budget is 0).
  void run_update(std::int64_t budget);
  void begin_gain();
  bool gain_rows(int& row, int end);
  ObservationResult gain_complete();
  void covariance_columns(int begin, int end);
  void finalize_update(ObservationResult r);
  bool depth_bounds_violated(int m);
  // EkfConfig::invariant_reset for the correction dx of the first n rows: P <- M P M^T, M = I +
  // v e_yaw^T. begin stores v and P's (corrected) yaw column; columns then applies M to columns
  // [begin, end) of the lower triangle and mirrors them.
  void begin_invariant_reset(int n, const Eigen::Ref<const Eigen::VectorXd>& dx);
  void invariant_reset_columns(int begin, int end);
  int drop_out_of_bounds(int m);

  EkfConfig config_;
  CameraModel camera_;
  int max_slots_;

  StateVector x_;
  StateMatrix P_;
  std::array<bool, hal::kMaxLandmarks> used_{};
  std::array<SlotInfo, hal::kMaxLandmarks> info_{};
  int landmark_count_ = 0;
  int active_dim_ = hal::kPoseDim;
  std::uint64_t update_counter_ = 0;
  Eigen::Vector3d last_motion_w_ = Eigen::Vector3d::Zero();

  // Workspaces of the batch update (m observations, 3m rows).
  std::array<int, hal::kMaxObservationsPerFrame> fuse_obs_{};
  std::array<Eigen::Matrix<double, 3, 6>, hal::kMaxObservationsPerFrame> Hp_{};
  std::array<Eigen::Matrix3d, hal::kMaxObservationsPerFrame> Hl_{};
  std::array<Eigen::Matrix3d, hal::kMaxObservationsPerFrame> R_{};
  std::array<bool, hal::kMaxObservationsPerFrame> young_{};
  std::array<bool, hal::kMaxObservationsPerFrame> out_of_bounds_{};
  std::array<PoseSighting, hal::kMaxObservationsPerFrame> sightings_{};
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxMeasDim, 1> nu_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxMeasDim, kMaxMeasDim> S_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxMeasDim, kMaxMeasDim> Sinv_;
  Eigen::LLT<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxMeasDim, kMaxMeasDim>>
      llt_;
  // W = [K | A^T] (n x 6m), V = [A ; K^T] (6m x n): P <- P - W V on the lower triangle.
  Eigen::MatrixXd W_;
  Eigen::MatrixXd V_;
  Eigen::MatrixXd PHt_;
  Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxStateDim> cross_;
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxStateDim> new_rows_;
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxStateDim, 1> dx_;
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxStateDim, 1> reset_v_;
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxStateDim, 1> reset_yaw_col_;
  double reset_yaw_var_ = 0.0;

  // The pending update (the batch of fuse_obs_, m_ observations, state dimension n_).
  std::int64_t step_budget_ = 0;
  UpdatePhase phase_ = UpdatePhase::kNone;
  int m_ = 0;
  int n_ = 0;
  int cursor_ = 0;
  std::array<int, hal::kMaxObservationsPerFrame> lms_{};

  UpdateStatus status_;
  EkfCounters counters_;
  double merge_test_ratio_ = -1.0;
};

}  // namespace cleanslam::slam_core
