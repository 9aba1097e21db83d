#include "cleanslam/slam_core/ekf.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "cleanslam/slam_core/camera_frame_measurement.hpp"
#include "cleanslam/slam_core/prediction_model.hpp"

namespace cleanslam::slam_core {

namespace {
constexpr int kPose = hal::kPoseDim;

bool finite2(double a, double b) {
  return std::isfinite(a) && std::isfinite(b);
}

// A symmetric Q positive semi-definite up to `tolerance`: no eigenvalue below -tolerance times
// its largest variance (at most its largest eigenvalue), which holds exactly when Q has a Cholesky
// factor once that much is added to its diagonal. (The pivoted LDL^T's D is no such test for a
// singular matrix: the dead reckoner's rank-deficient Q, whose eigenvalues are above -5e-16 of its
// largest, gave D entries of -0.6 %.)
bool positive_semidefinite(const Matrix6d& Q, double tolerance = 1e-9) {
  const double trace = Q.trace();
  if (!std::isfinite(trace) || trace < 0.0) {
    return false;
  }
  if (trace == 0.0) {
    return Q.isZero(0.0);
  }
  Matrix6d shifted = Q;
  shifted.diagonal().array() += tolerance * Q.diagonal().cwiseAbs().maxCoeff();
  // A factorization that overflowed reports success with a NaN factor.
  const Eigen::LLT<Matrix6d> llt(shifted);
  return llt.info() == Eigen::Success && llt.matrixLLT().allFinite();
}
}  // namespace

const char* to_string(ObservationResult r) {
  switch (r) {
    case ObservationResult::kFused:
      return "fused";
    case ObservationResult::kNonFinite:
      return "non_finite";
    case ObservationResult::kOutOfImage:
      return "out_of_image";
    case ObservationResult::kBehindCamera:
      return "behind_camera";
    case ObservationResult::kGate:
      return "gate";
    case ObservationResult::kParallelRay:
      return "parallel_ray";
    case ObservationResult::kNotPositiveDefinite:
      return "not_positive_definite";
    case ObservationResult::kInvalidSlot:
      return "invalid_slot";
    case ObservationResult::kOverCapacity:
      return "over_capacity";
    case ObservationResult::kDepthBound:
      return "depth_bound";
    case ObservationResult::kOutOfRange:
      return "out_of_range";
    case ObservationResult::kCount:
      break;
  }
  return "unknown";
}

Ekf::Ekf(const hal::Calibration& calibration, const EkfConfig& config)
    : config_(config),
      camera_(calibration.camera),
      max_slots_(std::clamp(config.max_landmarks, 0, hal::kMaxLandmarks)) {
  const int pool_dim = hal::kPoseDim + hal::kLandmarkDim * max_slots_;
  x_.setZero(pool_dim);
  P_.setZero(pool_dim, pool_dim);
  nu_.setZero(kMaxMeasDim);
  S_.setZero(kMaxMeasDim, kMaxMeasDim);
  Sinv_.setZero(kMaxMeasDim, kMaxMeasDim);
  W_.setZero(pool_dim, Eigen::Index{2} * kMaxMeasDim);
  V_.setZero(Eigen::Index{2} * kMaxMeasDim, pool_dim);
  PHt_.setZero(pool_dim, kMaxMeasDim);
  cross_.setZero(6, kMaxStateDim);
  new_rows_.setZero(3, kMaxStateDim);
  dx_.setZero(kMaxStateDim);
  reset_v_.setZero(kMaxStateDim);
  reset_yaw_col_.setZero(kMaxStateDim);
  start(Vector6d::Zero(), Matrix6d::Zero());
}

bool Ekf::reset(const Vector6d& camera_pose, const Matrix6d& P0) {
  const Matrix6d P0s = 0.5 * (P0 + P0.transpose());
  if (!camera_pose.allFinite() || camera_pose.cwiseAbs().maxCoeff() > kMaxAbsState ||
      !P0s.allFinite() || P0s.diagonal().maxCoeff() > kMaxVariance ||
      P0s.diagonal().tail<3>().maxCoeff() > kMaxAngleVariance || P0s.diagonal().minCoeff() < 0.0 ||
      !positive_semidefinite(P0s)) {
    return false;
  }
  start(camera_pose, P0s);
  return true;
}

void Ekf::start(const Vector6d& camera_pose, const Matrix6d& P0s) {
  // Past active_dim_ x and P are zero already: a deleted slot's rows are cleared.
  x_.head(active_dim_).setZero();
  P_.topLeftCorner(active_dim_, active_dim_).setZero();
  x_.head<6>() = camera_pose;
  P_.topLeftCorner<6, 6>() = P0s;
  used_.fill(false);
  info_.fill(SlotInfo{});
  landmark_count_ = 0;
  active_dim_ = kPose;
  update_counter_ = 0;
  last_motion_w_.setZero();
  status_ = UpdateStatus{};
  phase_ = UpdatePhase::kNone;
  m_ = 0;
}

bool Ekf::posterior_variance_ok(int i, double d) const {
  if (i >= kPose && !used_[static_cast<std::size_t>((i - kPose) / hal::kLandmarkDim)]) {
    return true;
  }
  return d > config_.min_variance && std::isfinite(d);
}

bool Ekf::state_in_range(int n, const Eigen::Ref<const Eigen::VectorXd>& dx) const {
  for (int i = 0; i < n; ++i) {
    const double v = x_(i) + dx(i);
    if (!(std::abs(v) <= kMaxAbsState)) {
      return false;
    }
  }
  return true;
}

bool Ekf::slot_used(int slot) const {
  return slot >= 0 && slot < hal::kMaxLandmarks && used_[static_cast<std::size_t>(slot)];
}

bool Ekf::valid_used_slot(int slot) const {
  return slot_used(slot);
}

bool Ekf::ray_to(int slot, Eigen::Vector3d& u, double& depth) const {
  if (!slot_used(slot)) {
    return false;
  }
  const Eigen::Vector3d d = x_.segment<3>(row_of(slot)) - x_.head<3>();
  depth = d.norm();
  if (!(depth > 0.0)) {
    return false;
  }
  u = d / depth;
  return true;
}

double Ekf::relative_depth_std(int slot) const {
  Eigen::Vector3d u;
  double depth = 0.0;
  if (!ray_to(slot, u, depth)) {
    return -1.0;
  }
  const int lm = row_of(slot);
  // Var of u^T (y - p): P_yy - P_yp - P_py + P_pp.
  const Eigen::Matrix3d Prel = P_.block<3, 3>(lm, lm) - P_.block<3, 3>(lm, 0) -
                               P_.block<3, 3>(0, lm) + P_.topLeftCorner<3, 3>();
  return std::sqrt(std::max(0.0, u.dot(Prel * u))) / depth;
}

bool Ekf::young(int slot) const {
  if (!config_.consider_young_landmarks || !slot_used(slot)) {
    return false;
  }
  return relative_depth_std(slot) > config_.young_depth_std_fraction;
}

Eigen::Vector3d Ekf::landmark(int slot) const {
  if (!slot_used(slot)) {
    return Eigen::Vector3d::Zero();
  }
  return x_.segment<3>(row_of(slot));
}

Eigen::Matrix3d Ekf::landmark_covariance(int slot) const {
  if (!slot_used(slot)) {
    return Eigen::Matrix3d::Zero();
  }
  return P_.block<3, 3>(row_of(slot), row_of(slot));
}

void Ekf::recompute_active_dim() {
  int highest = -1;
  for (int i = 0; i < hal::kMaxLandmarks; ++i) {
    if (used_[static_cast<std::size_t>(i)]) {
      highest = i;
    }
  }
  active_dim_ = row_of(highest + 1);
}

PredictStatus Ekf::predict(const OdometryIncrement& u) {
  finish_update();
  PredictStatus status;
  ++counters_.predictions;
  const Matrix6d Q = 0.5 * (u.Q + u.Q.transpose());
  const auto reject = [this, &status](PredictResult r) {
    status.result = r;
    ++counters_.predictions_rejected;
    return status;
  };
  if (!u.dx_c.allFinite() || !u.dpsi_c.allFinite() || !Q.allFinite() || !std::isfinite(u.dt_s)) {
    return reject(PredictResult::kNonFinite);
  }
  if (std::abs(x_(4)) > config_.max_abs_pitch_rad) {
    return reject(PredictResult::kPitchSingular);
  }
  if ((Q.diagonal().array() < 0.0).any() || !positive_semidefinite(Q)) {
    return reject(PredictResult::kNotPositiveDefinite);
  }
  const Vector6d pose = x_.head<6>();
  Vector6d ub;
  ub << u.dx_c, u.dpsi_c;
  Matrix6d F;
  Matrix6d G;
  prediction_jacobians(pose, ub.head<3>(), ub.tail<3>(), F, G);
  const Vector6d predicted = predict_pose(pose, ub.head<3>(), ub.tail<3>());  // eq. 3-4

  const Matrix6d Pxx = P_.topLeftCorner<6, 6>();
  Matrix6d Pn = F * Pxx * F.transpose() + G * Q * G.transpose();  // eq. 7
  const int nl = active_dim_ - kPose;
  cross_.resize(6, nl);
  if (nl > 0) {  // eq. 8
    cross_.noalias() = F.lazyProduct(P_.block(0, kPose, 6, nl));
  }
  // A finite increment can still overflow (an increment of 1e300 m): nothing is changed then.
  // So can one of 1e6 m or a variance of 1e12 m^2 leave the range (kMaxAbsState, kMaxVariance,
  // kMaxAngleVariance).
  if (!predicted.allFinite() || !Pn.allFinite() || !cross_.allFinite()) {
    return reject(PredictResult::kNonFinite);
  }
  if (predicted.cwiseAbs().maxCoeff() > kMaxAbsState || Pn.diagonal().maxCoeff() > kMaxVariance ||
      Pn.diagonal().tail<3>().maxCoeff() > kMaxAngleVariance) {
    return reject(PredictResult::kOutOfRange);
  }
  // Semi-definite P and Q predict a semi-definite P; what rounding of extreme inputs leaves
  // indefinite is refused.
  Pn = (0.5 * (Pn + Pn.transpose())).eval();
  if (!positive_semidefinite(Pn)) {
    return reject(PredictResult::kNotPositiveDefinite);
  }
  // Rounding of denormal variances can leave one a hair below zero.
  Pn.diagonal() = Pn.diagonal().cwiseMax(0.0);
  last_motion_w_ = G.topLeftCorner<3, 3>() * ub.head<3>();
  x_.head<6>() = predicted;
  x_(3) = wrap_angle(x_(3));
  x_(5) = wrap_angle(x_(5));
  if (nl > 0) {
    P_.block(0, kPose, 6, nl) = cross_;
    P_.block(kPose, 0, nl, 6) = cross_.transpose();
  }
  P_.topLeftCorner<6, 6>() = Pn;
  return status;
}

int Ekf::take_slot() {
  for (int i = 0; i < max_slots_; ++i) {
    if (!used_[static_cast<std::size_t>(i)]) {
      return i;
    }
  }
  int victim = -1;
  for (int i = 0; i < max_slots_; ++i) {
    const SlotInfo& s = info_[static_cast<std::size_t>(i)];
    if (victim < 0) {
      victim = i;
      continue;
    }
    const SlotInfo& v = info_[static_cast<std::size_t>(victim)];
    if (s.last_fused < v.last_fused || (s.last_fused == v.last_fused && s.fused < v.fused)) {
      victim = i;
    }
  }
  if (victim >= 0) {
    delete_landmark(victim);
    ++counters_.landmarks_replaced;
    --counters_.landmarks_deleted;
  }
  return victim;
}

int Ekf::initialize_landmark(double u_px, double v_px) {
  return initialize_landmark(u_px, v_px, config_.assumed_depth_m, config_.eps_ct_m);
}

int Ekf::initialize_landmark(double u_px, double v_px, double depth_m, double eps_ct_m) {
  finish_update();
  auto reject = [this](ObservationResult r) {
    counters_.rejections.add(r);
    return -1;
  };
  if (!finite2(u_px, v_px)) {
    return reject(ObservationResult::kNonFinite);
  }
  Eigen::Vector2d xn;
  if (!camera_.undistort(u_px, v_px, xn)) {
    return reject(ObservationResult::kOutOfImage);
  }
  if (max_slots_ == 0) {
    return reject(ObservationResult::kOverCapacity);
  }
  const Vector6d pose = x_.head<6>();
  const Eigen::Vector3d ct = CameraModel::ray(xn);
  const Eigen::Matrix3d C = rotation_zyx(pose(3), pose(4), pose(5));
  const double motion = last_motion_w_.norm();
  if (config_.min_ray_motion_angle_rad > 0.0 && motion > config_.min_motion_for_direction_m) {
    const double c = std::abs((C * ct).normalized().dot(last_motion_w_ / motion));
    if (std::acos(std::min(1.0, c)) < config_.min_ray_motion_angle_rad) {
      return reject(ObservationResult::kParallelRay);
    }
  }
  const double d = depth_m;
  if (!std::isfinite(d) || !std::isfinite(eps_ct_m) || !(d > config_.min_depth_m)) {
    return reject(ObservationResult::kNonFinite);
  }
  const Eigen::Vector3d vc = point_at_depth(ct, d);  // eq. 13
  Eigen::Matrix<double, 3, 6> T;
  const Eigen::Vector3d y = landmark_from_camera_point(pose, vc, &T);  // eq. 39, 41-42
  const Eigen::Matrix3d Rv = measurement_covariance(
      ct, eps_ct_m, normal_noise(d, config_.eps_trk_px, config_.eps_cal_px, camera_.focal_px()));
  Eigen::Matrix3d Py = T * P_.topLeftCorner<6, 6>() * T.transpose() + C * Rv * C.transpose();
  Py = 0.5 * (Py + Py.transpose()).eval();  // eq. 40
  if (!y.allFinite() || !Py.allFinite()) {
    return reject(ObservationResult::kNonFinite);
  }
  if (y.cwiseAbs().maxCoeff() > kMaxAbsState || Py.diagonal().maxCoeff() > kMaxVariance) {
    return reject(ObservationResult::kOutOfRange);
  }
  if (Eigen::LLT<Eigen::Matrix3d>(Py).info() != Eigen::Success) {
    return reject(ObservationResult::kNotPositiveDefinite);
  }
  const int slot = take_slot();
  if (slot < 0) {
    return reject(ObservationResult::kOverCapacity);
  }
  const int lm = row_of(slot);
  active_dim_ = std::max(active_dim_, lm + 3);
  const int n = active_dim_;
  new_rows_.resize(3, n);
  new_rows_.noalias() = T.lazyProduct(P_.block(0, 0, 6, n));  // eq. 44-45
  P_.block(lm, 0, 3, n) = new_rows_;
  P_.block(0, lm, n, 3) = new_rows_.transpose();
  P_.block<3, 3>(lm, lm) = Py;  // eq. 43
  x_.segment<3>(lm) = y;
  used_[static_cast<std::size_t>(slot)] = true;
  info_[static_cast<std::size_t>(slot)] = SlotInfo{update_counter_, 0};
  ++landmark_count_;
  ++counters_.landmarks_initialized;
  return slot;
}

void Ekf::delete_landmark(int slot) {
  finish_update();
  if (!slot_used(slot)) {
    return;
  }
  const int lm = row_of(slot);
  const int n = active_dim_;
  P_.block(lm, 0, 3, n).setZero();
  P_.block(0, lm, n, 3).setZero();
  x_.segment<3>(lm).setZero();
  used_[static_cast<std::size_t>(slot)] = false;
  info_[static_cast<std::size_t>(slot)] = SlotInfo{};
  --landmark_count_;
  ++counters_.landmarks_deleted;
  recompute_active_dim();
}

ObservationResult Ekf::measure(const Observation& o, Eigen::Vector3d& z, Eigen::Matrix3d& R,
                               Eigen::Vector3d& h, Eigen::Matrix<double, 3, 6>& Hp,
                               Eigen::Matrix3d& Hl) const {
  if (!valid_used_slot(o.slot)) {
    return ObservationResult::kInvalidSlot;
  }
  if (!finite2(o.u_px, o.v_px)) {
    return ObservationResult::kNonFinite;
  }
  Eigen::Vector2d n;
  if (!camera_.undistort(o.u_px, o.v_px, n)) {
    return ObservationResult::kOutOfImage;
  }
  const Eigen::Vector3d ct = CameraModel::ray(n);
  const Eigen::Vector3d c_hat = ct.normalized();
  const Vector6d pose = x_.head<6>();
  const Eigen::Vector3d y = x_.segment<3>(row_of(o.slot));
  h = predict_camera_point(pose, y);  // eq. 21
  const double depth = h.dot(c_hat);  // the predicted depth along the measured ray
  if (!(h.x() > config_.min_depth_m) || !(depth > config_.min_depth_m)) {
    return ObservationResult::kBehindCamera;
  }
  z = point_at_depth(ct, depth);  // eq. 13
  R = measurement_covariance(
      ct, config_.eps_ct_m,
      normal_noise(depth, config_.eps_trk_px, config_.eps_cal_px, camera_.focal_px()));
  measurement_jacobian(pose, y, Hp, Hl);  // eq. 22-24
  if (!z.allFinite() || !R.allFinite() || !Hp.allFinite()) {
    return ObservationResult::kNonFinite;
  }
  return ObservationResult::kFused;
}

const UpdateStatus& Ekf::update(const Observation* obs, int count) {
  finish_update();
  status_ = UpdateStatus{};
  status_.received = count;
  ++update_counter_;
  if (obs == nullptr || count < 0) {
    count = 0;
  }
  const Vector6d prior_pose = x_.head<6>();
  Vector6d offset = Vector6d::Zero();
  Vector6d lin_pose;
  if (config_.solve_pose_beyond_linear_range && linearization_pose(obs, count, lin_pose)) {
    offset = lin_pose - prior_pose;
    offset(3) = wrap_angle(offset(3));
    offset(5) = wrap_angle(offset(5));
    x_.head<6>() = lin_pose;  // measure() and pixel_gate() linearize here; restored below
    ++counters_.pose_solves;
  }
  int m = 0;
  for (int i = 0; i < count; ++i) {
    if (i >= hal::kMaxObservationsPerFrame) {
      counters_.rejections.add(ObservationResult::kOverCapacity);
      ++status_.rejected;
      continue;
    }
    const Observation& o = obs[i];
    ObservationStatus& st = status_.observations[static_cast<std::size_t>(status_.count++)];
    st.slot = o.slot;
    ObservationResult r = ObservationResult::kFused;
    for (int j = 0; j < m; ++j) {
      if (status_.observations[static_cast<std::size_t>(fuse_obs_[static_cast<std::size_t>(j)])]
              .slot == o.slot) {
        r = ObservationResult::kInvalidSlot;
      }
    }
    Eigen::Vector3d z;
    Eigen::Vector3d h;
    Eigen::Matrix3d R;
    Eigen::Matrix<double, 3, 6> Hp;
    Eigen::Matrix3d Hl;
    if (r == ObservationResult::kFused) {
      r = measure(o, z, R, h, Hp, Hl);
    }
    if (r == ObservationResult::kFused) {
      const int lm = row_of(o.slot);
      const Eigen::Matrix<double, 3, 3> HpPxl = Hp * P_.block<6, 3>(0, lm) * Hl.transpose();
      Eigen::Matrix3d Sj = Hp * P_.topLeftCorner<6, 6>() * Hp.transpose() + HpPxl +
                           HpPxl.transpose() + Hl * P_.block<3, 3>(lm, lm) * Hl.transpose() + R;
      Sj = 0.5 * (Sj + Sj.transpose()).eval();
      const Eigen::LLT<Eigen::Matrix3d> llt(Sj);
      // The iterated EKF's innovation: the measurement linearized at the solved pose, evaluated at
      // the prior's.
      st.innovation = z - h + Hp * offset;
      st.innovation_covariance = Sj;
      if (llt.info() != Eigen::Success) {
        r = ObservationResult::kNotPositiveDefinite;
      } else {
        st.test_ratio = st.innovation.dot(llt.solve(st.innovation)) / config_.gate_chi2;
        r = pixel_gate(o, offset, st);
        if (r == ObservationResult::kFused && !(st.test_ratio <= 1.0)) {
          r = ObservationResult::kGate;
        }
      }
    }
    st.result = r;
    if (r != ObservationResult::kFused) {
      counters_.rejections.add(r);
      ++status_.rejected;
      continue;
    }
    const auto mi = static_cast<std::size_t>(m);
    fuse_obs_[mi] = status_.count - 1;
    Hp_[mi] = Hp;
    Hl_[mi] = Hl;
    R_[mi] = R;
    young_[mi] = young(o.slot);
    nu_.segment<3>(3 * Eigen::Index{m}) = st.innovation;
    ++m;
  }
  x_.head<6>() = prior_pose;
  m_ = m;
  if (m == 0) {
    return status_;
  }
  phase_ = UpdatePhase::kGain;
  run_update(step_budget_);
  return status_;
}

void Ekf::finalize_update(ObservationResult r) {
  phase_ = UpdatePhase::kNone;
  dx_.resize(kMaxStateDim);
  const int m = m_;
  if (m == 0) {
    return;
  }
  for (int j = 0; j < m; ++j) {
    ObservationStatus& st =
        status_.observations[static_cast<std::size_t>(fuse_obs_[static_cast<std::size_t>(j)])];
    st.result = r;
    if (r == ObservationResult::kFused) {
      SlotInfo& info = info_[static_cast<std::size_t>(st.slot)];
      if (young_[static_cast<std::size_t>(j)]) {
        ++counters_.consider_observations;
      }
      info.last_fused = update_counter_;
      ++info.fused;
      ++status_.fused;
    } else {
      counters_.rejections.add(r);
      ++status_.rejected;
    }
  }
  status_.applied = r == ObservationResult::kFused;
  if (status_.applied) {
    ++counters_.updates_applied;
  }
}

ObservationResult Ekf::pixel_gate(const Observation& o, const Vector6d& offset,
                                  ObservationStatus& st) const {
  if (!(config_.gate_pixel_chi2 > 0.0)) {
    return ObservationResult::kFused;
  }
  PixelPrediction p;
  if (!predict_pixel(o.slot, p)) {
    return ObservationResult::kBehindCamera;
  }
  st.pixel_innovation = Eigen::Vector2d(o.u_px, o.v_px) - p.uv;
  if (!offset.isZero(0.0)) {
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 6> Jp;
    Eigen::Matrix<double, 2, 3> Jl;
    double depth = 0.0;
    if (!pixel_jacobian(o.slot, uv, Jp, Jl, depth)) {
      return ObservationResult::kBehindCamera;
    }
    st.pixel_innovation += Jp * offset;
  }
  const Eigen::LLT<Eigen::Matrix2d> llt(p.S);
  if (llt.info() != Eigen::Success) {
    return ObservationResult::kNotPositiveDefinite;
  }
  st.pixel_test_ratio =
      st.pixel_innovation.dot(llt.solve(st.pixel_innovation)) / config_.gate_pixel_chi2;
  return st.pixel_test_ratio <= 1.0 ? ObservationResult::kFused : ObservationResult::kGate;
}

void Ekf::set_update_step(std::int64_t work) {
  step_budget_ = std::max<std::int64_t>(0, work);
}

bool Ekf::continue_update() {
  if (phase_ != UpdatePhase::kNone) {
    run_update(step_budget_);
  }
  return phase_ == UpdatePhase::kNone;
}

void Ekf::finish_update() {
  if (phase_ != UpdatePhase::kNone) {
    run_update(0);
  }
}

// The batch update as resumable work (eq. 25-27): the gain's set-up, its rows a few at a time,
// the state correction, then the covariance correction a few columns at a time. Each piece's work
// is estimated in units of about one instruction (host callgrind counts of the pieces: a gain row,
// coefficient-wise products, costs about eight per multiply-add, a covariance column, a vectorized
// matrix-vector product, about 1.5 plus its set-up); a step does pieces until the budget is spent
// (at least one). Gain rows go in multiples of four (of every SIMD width: a row's rounding does not
// depend on where a step starts), columns are independent: the result does not depend on the
// budget.
void Ekf::run_update(std::int64_t budget) {
  constexpr int kRowsPerPiece = 4;
  constexpr std::int64_t kRowWork = 8;
  constexpr std::int64_t kColumnWork = 400;  // a matrix-vector product's set-up
  const auto over = [budget](std::int64_t spent) { return budget > 0 && spent >= budget; };
  std::int64_t spent = 0;
  while (phase_ != UpdatePhase::kNone && !over(spent)) {
    const std::int64_t n = n_;
    const std::int64_t k = 3 * std::int64_t{m_};
    switch (phase_) {
      case UpdatePhase::kGain:
        begin_gain();
        spent += 2 * (27 * std::int64_t{active_dim_} * m_ + 3 * k * k * k);
        break;
      case UpdatePhase::kGainRows: {
        int row = cursor_;
        int end = n_;
        if (budget > 0) {
          const std::int64_t per_row = kRowWork * (2 * k * k + 4 * k);
          const std::int64_t rows = std::max<std::int64_t>(1, (budget - spent) / per_row);
          end = static_cast<int>(std::min<std::int64_t>(
              n, row + (rows + kRowsPerPiece - 1) / kRowsPerPiece * kRowsPerPiece));
        }
        spent += (end - row) * kRowWork * (2 * k * k + 4 * k);
        if (!gain_rows(row, end)) {
          finalize_update(ObservationResult::kNotPositiveDefinite);
          break;
        }
        cursor_ = row;
        if (cursor_ < n_) {
          break;
        }
        const ObservationResult r = gain_complete();
        spent += n * k;
        if (r == ObservationResult::kDepthBound) {
          m_ = drop_out_of_bounds(m_);
          dx_.resize(kMaxStateDim);
          if (m_ > 0) {
            phase_ = UpdatePhase::kGain;
          } else {
            finalize_update(ObservationResult::kFused);
          }
        } else if (r != ObservationResult::kFused) {
          finalize_update(r);
        } else {
          // The state correction, with the pose's covariance columns in the same step: pose()
          // and pose_covariance() are the posterior's from here on.
          x_.head(n_) += dx_;
          x_(3) = wrap_angle(x_(3));
          x_(5) = wrap_angle(x_(5));
          covariance_columns(0, kPose);
          spent += kPose * (n * (3 * k + 3) + kColumnWork);
          if (config_.invariant_reset) {
            begin_invariant_reset(n_, dx_.head(n_));
            invariant_reset_columns(0, kPose);
            spent += kPose * (3 * n);
          }
          cursor_ = kPose;
          phase_ = UpdatePhase::kCovariance;
        }
        break;
      }
      case UpdatePhase::kCovariance: {
        int j = cursor_;
        std::int64_t cost = 0;
        do {
          cost += (n - j) * (3 * k + (config_.invariant_reset ? 6 : 3)) + kColumnWork;
          ++j;
        } while (j < n_ && !over(spent + cost));
        covariance_columns(cursor_, j);
        if (config_.invariant_reset) {
          invariant_reset_columns(cursor_, j);
        }
        spent += cost;
        cursor_ = j;
        if (cursor_ >= n_) {
          finalize_update(ObservationResult::kFused);
        }
        break;
      }
      case UpdatePhase::kNone:
        break;
    }
  }
}

void Ekf::begin_gain() {
  const int m = m_;
  const int n = active_dim_;
  const int k = 3 * m;
  n_ = n;
  cursor_ = 0;
  for (int j = 0; j < m; ++j) {
    const auto& st =
        status_.observations[static_cast<std::size_t>(fuse_obs_[static_cast<std::size_t>(j)])];
    lms_[static_cast<std::size_t>(j)] = row_of(st.slot);
  }
  // PHt = P H^T, H sparse: pose columns and one landmark's three columns per observation.
  auto PHt = PHt_.topLeftCorner(n, k);
  for (Eigen::Index j = 0; j < m; ++j) {
    const auto js = static_cast<std::size_t>(j);
    PHt.middleCols<3>(3 * j).noalias() = P_.block(0, 0, n, 6).lazyProduct(Hp_[js].transpose());
    PHt.middleCols<3>(3 * j).noalias() +=
        P_.block(0, lms_[js], n, 3).lazyProduct(Hl_[js].transpose());
  }
  S_.resize(k, k);
  for (Eigen::Index i = 0; i < m; ++i) {
    const auto is = static_cast<std::size_t>(i);
    for (Eigen::Index j = 0; j < m; ++j) {
      S_.block<3, 3>(3 * i, 3 * j) =
          Hp_[is] * PHt.block<6, 3>(0, 3 * j) + Hl_[is] * PHt.block<3, 3>(lms_[is], 3 * j);
    }
    S_.block<3, 3>(3 * i, 3 * i) += R_[is];
  }
  for (int i = 0; i < k; ++i) {
    for (int j = i + 1; j < k; ++j) {
      const double a = 0.5 * (S_(i, j) + S_(j, i));
      S_(i, j) = a;
      S_(j, i) = a;
    }
  }
  llt_.compute(S_);
  // S's condition, as its Cholesky pivots' ratio: beyond kMaxInnovationCondition the gain keeps
  // fewer than about five significant digits in double precision, and its covariance correction
  // can leave P indefinite (found by fuzzing: a landmark of 490 m std. dev. seen with 30 m along
  // its ray and 0.15 mm across).
  constexpr double kMaxInnovationCondition = 1e11;
  const auto pivots = llt_.matrixLLT().diagonal().head(k).cwiseAbs2();
  if (llt_.info() != Eigen::Success ||
      !(pivots.maxCoeff() <= kMaxInnovationCondition * pivots.minCoeff())) {
    finalize_update(ObservationResult::kNotPositiveDefinite);
    return;
  }
  Sinv_.setIdentity(k, k);
  llt_.solveInPlace(Sinv_);
  phase_ = UpdatePhase::kGainRows;
}

// Rows [row, end) of W = [K | A^T] with K = PHt S^-1 (eq. 27) and A^T = PHt - K S / 2, and the
// matching columns of V = [A ; K^T]; false when a used row's posterior variance would not stay
// positive (the PSD guard). row ends where the rows were done.
bool Ekf::gain_rows(int& row, int end) {
  const int k = 3 * m_;
  const int r0 = row;
  const int rc = end - r0;
  auto PHt = PHt_.block(r0, 0, rc, k);
  auto W = W_.block(r0, 0, rc, 2 * k);
  W.leftCols(k).noalias() = PHt.lazyProduct(Sinv_);
  for (Eigen::Index j = 0; j < m_; ++j) {  // consider update: only the young landmark's own rows
    if (young_[static_cast<std::size_t>(j)]) {
      const int lm = lms_[static_cast<std::size_t>(j)];
      const int below = std::clamp(lm, r0, end);
      const int above = std::clamp(lm + 3, r0, end);
      W_.block(r0, 3 * j, below - r0, 3).setZero();
      W_.block(above, 3 * j, end - above, 3).setZero();
    }
  }
  W.rightCols(k) = PHt;
  W.rightCols(k).noalias() -= 0.5 * W.leftCols(k).lazyProduct(S_);
  V_.block(0, r0, k, rc) = W.rightCols(k).transpose();
  V_.block(k, r0, k, rc) = W.leftCols(k).transpose();
  for (int i = r0; i < end; ++i) {
    row = i + 1;
    const double d = P_(i, i) - W_.row(i).head(2 * k).dot(V_.col(i).head(2 * k));
    if (!posterior_variance_ok(i, d)) {
      return false;
    }
  }
  return true;
}

ObservationResult Ekf::gain_complete() {
  const int n = n_;
  const int k = 3 * m_;
  dx_.resize(n);
  dx_.noalias() = W_.topLeftCorner(n, k) * nu_.head(k);  // eq. 25
  if (!dx_.allFinite()) {
    return ObservationResult::kNonFinite;
  }
  if (!state_in_range(n, dx_)) {
    return ObservationResult::kOutOfRange;
  }
  if (config_.depth_bounds && depth_bounds_violated(m_)) {
    return ObservationResult::kDepthBound;
  }
  return ObservationResult::kFused;
}

// Joseph form (eq. 26 made symmetric): P - K A - A^T K^T on the lower triangle of columns
// [begin, end), each mirrored into its row at once (a column's later updates touch only rows
// below it).
void Ekf::covariance_columns(int begin, int end) {
  const int n = n_;
  const int k2 = 6 * m_;
  const auto W = W_.topLeftCorner(n, k2);
  const auto V = V_.topLeftCorner(k2, n);
  for (int j = begin; j < end; ++j) {
    P_.col(j).segment(j, n - j).noalias() -= W.bottomRows(n - j) * V.col(j);
    P_.row(j).segment(j + 1, n - j - 1) = P_.col(j).segment(j + 1, n - j - 1).transpose();
  }
}

bool Ekf::depth_bounds_violated(int m) {
  Vector6d pose = x_.head<6>() + dx_.head<6>();
  pose(3) = wrap_angle(pose(3));
  pose(5) = wrap_angle(pose(5));
  bool any = false;
  for (int j = 0; j < m; ++j) {
    const auto js = static_cast<std::size_t>(j);
    const int slot = status_.observations[static_cast<std::size_t>(fuse_obs_[js])].slot;
    const int lm = row_of(slot);
    const Eigen::Vector3d y = x_.segment<3>(lm) + dx_.segment<3>(lm);
    const double depth = predict_camera_point(pose, y).x();
    out_of_bounds_[js] = !(depth > config_.min_depth_m) ||
                         (config_.max_depth_m > 0.0 && depth > config_.max_depth_m);
    any = any || out_of_bounds_[js];
  }
  return any;
}

int Ekf::drop_out_of_bounds(int m) {
  int q = 0;
  for (int j = 0; j < m; ++j) {
    const auto js = static_cast<std::size_t>(j);
    if (out_of_bounds_[js]) {
      ObservationStatus& st = status_.observations[static_cast<std::size_t>(fuse_obs_[js])];
      st.result = ObservationResult::kDepthBound;
      counters_.rejections.add(ObservationResult::kDepthBound);
      ++status_.rejected;
      continue;
    }
    const auto qs = static_cast<std::size_t>(q);
    fuse_obs_[qs] = fuse_obs_[js];
    Hp_[qs] = Hp_[js];
    Hl_[qs] = Hl_[js];
    R_[qs] = R_[js];
    young_[qs] = young_[js];
    nu_.segment<3>(3 * Eigen::Index{q}) = nu_.segment<3>(3 * Eigen::Index{j});
    ++q;
  }
  return q;
}

bool Ekf::pixel_jacobian(int slot, Eigen::Vector2d& uv, Eigen::Matrix<double, 2, 6>& Jp,
                         Eigen::Matrix<double, 2, 3>& Jl, double& depth) const {
  const Vector6d pose = x_.head<6>();
  const Eigen::Vector3d y = x_.segment<3>(row_of(slot));
  const Eigen::Vector3d h = predict_camera_point(pose, y);
  depth = h.x();
  Eigen::Matrix<double, 3, 6> Hp;
  Eigen::Matrix3d Hl;
  measurement_jacobian(pose, y, Hp, Hl);
  Eigen::Matrix<double, 2, 3> J;
  if (!(depth > config_.min_depth_m) || !camera_.project(h, uv, &J)) {
    return false;
  }
  Jp = J * Hp;
  Jl = J * Hl;
  return true;
}

bool Ekf::predict_pixel(int slot, PixelPrediction& out) const {
  out = PixelPrediction{};
  if (!slot_used(slot)) {
    return false;
  }
  Eigen::Matrix<double, 2, 6> Jp;
  Eigen::Matrix<double, 2, 3> Jl;
  if (!pixel_jacobian(slot, out.uv, Jp, Jl, out.depth_m)) {
    return false;
  }
  const int lm = row_of(slot);
  const Eigen::Matrix2d cross = Jp * P_.block<6, 3>(0, lm) * Jl.transpose();
  const double r =
      config_.eps_trk_px * config_.eps_trk_px + config_.eps_cal_px * config_.eps_cal_px;
  out.S = Jp * P_.topLeftCorner<6, 6>() * Jp.transpose() + cross + cross.transpose() +
          Jl * P_.block<3, 3>(lm, lm) * Jl.transpose() + r * Eigen::Matrix2d::Identity();
  out.S(0, 1) = out.S(1, 0);  // the lower triangle, which the Cholesky factorizations read
  if (!out.uv.allFinite() || !out.S.allFinite()) {  // a projection that overflows
    out = PixelPrediction{};
    return false;
  }
  out.in_front = true;
  return true;
}

int Ekf::joint_pixel_innovation(std::span<const Observation> obs, std::span<double> nu,
                                std::span<double> S) const {
  constexpr auto kMax = static_cast<std::size_t>(hal::kMaxObservationsPerFrame);
  if (obs.size() > kMax || nu.size() < 2 * obs.size() || S.size() < 4 * obs.size() * obs.size()) {
    return -1;
  }
  const auto count = static_cast<int>(obs.size());
  if (count == 0) {
    return 0;
  }
  std::array<Eigen::Matrix<double, 2, 6>, hal::kMaxObservationsPerFrame> Jp;
  std::array<Eigen::Matrix<double, 2, 3>, hal::kMaxObservationsPerFrame> Jl;
  std::array<int, hal::kMaxObservationsPerFrame> lm{};
  for (int i = 0; i < count; ++i) {
    const auto is = static_cast<std::size_t>(i);
    const Observation& o = obs[is];
    Eigen::Vector2d uv;
    double depth = 0.0;
    if (!slot_used(o.slot) || !finite2(o.u_px, o.v_px) ||
        !pixel_jacobian(o.slot, uv, Jp[is], Jl[is], depth)) {
      return -1;
    }
    lm[is] = row_of(o.slot);
    nu[2 * is] = o.u_px - uv.x();
    nu[2 * is + 1] = o.v_px - uv.y();
  }
  const int dim = 2 * count;
  Eigen::Map<Eigen::MatrixXd> Sm(S.data(), dim, dim);
  const double r =
      config_.eps_trk_px * config_.eps_trk_px + config_.eps_cal_px * config_.eps_cal_px;
  const Matrix6d Pxx = P_.topLeftCorner<6, 6>();
  for (Eigen::Index i = 0; i < count; ++i) {
    const auto is = static_cast<std::size_t>(i);
    for (Eigen::Index j = i; j < count; ++j) {
      const auto js = static_cast<std::size_t>(j);
      Sm.block<2, 2>(2 * i, 2 * j) = Jp[is] * Pxx * Jp[js].transpose() +
                                     Jp[is] * P_.block<6, 3>(0, lm[js]) * Jl[js].transpose() +
                                     Jl[is] * P_.block<3, 6>(lm[is], 0) * Jp[js].transpose() +
                                     Jl[is] * P_.block<3, 3>(lm[is], lm[js]) * Jl[js].transpose();
    }
    Sm.block<2, 2>(2 * i, 2 * i) += r * Eigen::Matrix2d::Identity();
    Sm(2 * i + 1, 2 * i) = Sm(2 * i, 2 * i + 1) =
        0.5 * (Sm(2 * i + 1, 2 * i) + Sm(2 * i, 2 * i + 1));
  }
  for (int c = 0; c < dim; ++c) {
    for (int r2 = c + 1; r2 < dim; ++r2) {
      if (r2 / 2 != c / 2) {
        Sm(r2, c) = Sm(c, r2);
      }
    }
  }
  if (!Sm.allFinite() || !Eigen::Map<const Eigen::VectorXd>(nu.data(), dim).allFinite()) {
    return -1;
  }
  return count;
}

hal::PoseEstimate Ekf::body_pose_estimate(hal::TimeNs t_ns) const {
  hal::PoseEstimate out;
  out.t_ns = t_ns;
  const Vector6d cam = x_.head<6>();
  const Vector6d body = body_pose_from_camera_pose(cam, camera_);
  out.position_m = {body(0), body(1), body(2)};
  const Eigen::Quaterniond q = quaternion_from_zyx(body(3), body(4), body(5));
  out.orientation_wxyz = {q.w(), q.x(), q.y(), q.z()};
  // d body / d camera pose by central differences (angles wrapped).
  Matrix6d J;
  constexpr double kStep = 1e-6;
  for (int c = 0; c < 6; ++c) {
    Vector6d a = cam;
    Vector6d b = cam;
    a(c) += kStep;
    b(c) -= kStep;
    Vector6d d = body_pose_from_camera_pose(a, camera_) - body_pose_from_camera_pose(b, camera_);
    for (int r = 3; r < 6; ++r) {
      d(r) = wrap_angle(d(r));
    }
    J.col(c) = d / (2.0 * kStep);
  }
  const Matrix6d Pb = J * P_.topLeftCorner<6, 6>() * J.transpose();
  for (Eigen::Index r = 0; r < 6; ++r) {
    for (Eigen::Index c = 0; c < 6; ++c) {
      out.covariance[static_cast<std::size_t>(6 * r + c)] = 0.5 * (Pb(r, c) + Pb(c, r));
    }
  }
  out.landmarks_in_map = static_cast<std::uint16_t>(landmark_count_);
  // While an update is pending, the landmarks it is fusing.
  out.landmarks_in_view = static_cast<std::uint16_t>(update_pending() ? m_ : status_.fused);
  if (landmark_count_ < 3) {
    out.health |= hal::kFewLandmarks;
  }
  return out;
}

}  // namespace cleanslam::slam_core
