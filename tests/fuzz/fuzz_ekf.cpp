// Fuzz target for slam_core::Ekf. The first bytes choose the filter's options, its pool size and a
// reset; the rest is a sequence of up to 32 operations (prediction, landmark initialization,
// deletion and merge, batch updates at once or in bounded steps, pixel predictions, the body pose,
// a reset), each plausible or, when its opcode asks, with one input replaced by NaN, an infinity,
// an extreme or a raw 8-byte double. After every operation:
//  - x and P are finite over the active rows, P is exactly symmetric with a non-negative
//    diagonal, its pose block is positive semi-definite (all of it when no update is pending),
//    and the rows and columns of unused slots are zero;
//  - the landmark count and active_dim match the used mask;
//  - a refused call (prediction, initialization, deletion, merge, an update that fused
//    nothing) left x and P unchanged and was counted; a prediction leaves the map alone;
//  - a second filter given the same calls with every update done at once agrees exactly
//    whenever no update is pending (the chunked result equals the one-shot one).
// At the end of the input both filters' x and P are zero past active_dim.
// A reset with a hostile pose or covariance is refused (nothing changed) or takes a valid one.
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "cleanslam/hal/calibration.hpp"
#include "cleanslam/hal/capacities.hpp"
#include "cleanslam/slam_core/ekf.hpp"
#include "cleanslam/slam_core/ekf_config.hpp"
#include "cleanslam/slam_core/odometry_increment.hpp"
#include "symmetric_eigen.hpp"

namespace {

namespace hal = cleanslam::hal;
using cleanslam::slam_core::Ekf;
using cleanslam::slam_core::EkfConfig;
using cleanslam::slam_core::Matrix6d;
using cleanslam::slam_core::Observation;
using cleanslam::slam_core::ObservationResult;
using cleanslam::slam_core::OdometryIncrement;
using cleanslam::slam_core::PixelPrediction;
using cleanslam::slam_core::PredictResult;
using cleanslam::slam_core::Vector6d;

constexpr int kMaxOperations = 32;
// The largest pool the setup chooses, and the state it spans: snapshots and copies of P are held
// at that size without allocating.
constexpr int kMaxPool = 12;
constexpr int kMaxActiveDim = hal::kPoseDim + hal::kLandmarkDim * kMaxPool;
using ActiveVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxActiveDim, 1>;
using ActiveMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxActiveDim, kMaxActiveDim>;
// Relative tolerance of the positive semi-definiteness checks (eigenvalues, diagonal).
constexpr double kPsdTolerance = 1e-9;

class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  [[nodiscard]] bool done() const { return pos_ >= size_; }
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : std::uint8_t{0}; }
  double raw() {
    std::array<std::uint8_t, sizeof(double)> b{};
    for (std::uint8_t& c : b) {
      c = byte();
    }
    double d = 0.0;
    std::memcpy(&d, b.data(), sizeof d);
    return d;
  }
  // lo..hi in 256 steps.
  double range(double lo, double hi) { return lo + (hi - lo) * byte() / 255.0; }
  double log_range(double lo_exp, double hi_exp) { return std::pow(10.0, range(lo_exp, hi_exp)); }
  // NaN, an infinity, an extreme, or a raw double (a quarter of the time).
  double hostile() {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    constexpr double kMax = std::numeric_limits<double>::max();
    constexpr std::array kSpecial{std::numeric_limits<double>::quiet_NaN(),
                                  kInf,
                                  -kInf,
                                  kMax,
                                  -kMax,
                                  std::numeric_limits<double>::denorm_min(),
                                  1e300,
                                  -1e300,
                                  1e154,
                                  0.0,
                                  -0.0,
                                  -1.0};
    const std::uint8_t b = byte();
    return b < 16 * kSpecial.size() ? kSpecial[b % kSpecial.size()] : raw();
  }
  // Replaces one of the fields' values with a hostile one.
  void corrupt(std::initializer_list<std::span<double>> fields) {
    std::size_t total = 0;
    for (const std::span<double> f : fields) {
      total += f.size();
    }
    std::size_t i = byte() % total;
    for (const std::span<double> f : fields) {
      if (i < f.size()) {
        f[i] = hostile();
        return;
      }
      i -= f.size();
    }
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

template <typename Matrix>
std::span<double> field(Matrix& m) {
  return {m.data(), static_cast<std::size_t>(m.size())};
}
std::span<double> field(double& d) {
  return {&d, 1};
}

// Diagonal std. devs 10^lo..10^hi (or 0) and one correlation (-1..1): PSD.
Matrix6d covariance(ByteReader& in, double lo_exp, double hi_exp) {
  Vector6d sigma;
  for (int i = 0; i < 6; ++i) {
    const std::uint8_t b = in.byte();
    sigma(i) = b == 0 ? 0.0 : std::pow(10.0, lo_exp + (hi_exp - lo_exp) * b / 255.0);
  }
  Matrix6d C = Matrix6d::Identity();
  const int i = in.byte() % 6;
  const int j = in.byte() % 6;
  const double rho = in.range(-1.0, 1.0);
  if (i != j) {
    C(i, j) = rho;
    C(j, i) = rho;
  }
  return sigma.asDiagonal() * C * sigma.asDiagonal();
}

struct Setup {
  std::array<std::uint8_t, 3> bytes{};
  hal::Calibration calibration;
  EkfConfig config;
};

Setup read_setup(ByteReader& in) {
  Setup s;
  for (std::uint8_t& b : s.bytes) {
    b = in.byte();
  }
  const unsigned bits = s.bytes[0] | (static_cast<unsigned>(s.bytes[1]) << 8U);
  const auto bit = [bits](unsigned b) { return ((bits >> b) & 1U) != 0; };
  EkfConfig& c = s.config;
  c.consider_young_landmarks = bit(0);
  c.depth_bounds = bit(1);
  // Bits 2, 3, 4, 7, 12 and 14 are unused.
  c.invariant_reset = bit(5);
  c.merge_considers_kept = bit(6);
  c.gate_pixel_chi2 = bit(10) ? 0.0 : c.gate_pixel_chi2;
  c.max_depth_m = bit(11) ? 8.0 : 0.0;
  if (bit(13)) {
    s.calibration.camera.distortion = {-0.1, 0.02, 0.0005, -0.0003};
  }
  c.min_ray_motion_angle_rad = bit(15) ? 0.0 : c.min_ray_motion_angle_rad;
  c.max_landmarks = s.bytes[2] % (kMaxPool + 1);
  // The filters' key: the bits and the pool size read above.
  s.bytes[0] &= 0x63U;
  s.bytes[1] &= 0xACU;
  s.bytes[2] = static_cast<std::uint8_t>(c.max_landmarks);
  return s;
}

// Construction allocates and clears the filter's workspaces (about 100 KB for the pools here),
// more than a short input costs: the filters of the 256 most recently used setups are kept, and
// reset for each input. The key holds only the bits read_setup reads, so that inputs that differ
// in the unused ones share their filters.
struct Filters {
  std::array<std::uint8_t, 3> setup_bytes{};
  std::uint64_t last_use = 0;
  std::unique_ptr<Ekf> chunked;
  std::unique_ptr<Ekf> one_shot;
};

Filters& filters_for(const Setup& s) {
  static std::array<Filters, 256> cache;
  static std::uint64_t uses = 0;
  Filters* oldest = &cache.front();
  for (Filters& f : cache) {
    if (f.chunked && f.setup_bytes == s.bytes) {
      f.last_use = ++uses;
      return f;
    }
    if (f.last_use < oldest->last_use) {
      oldest = &f;
    }
  }
  *oldest = {s.bytes, ++uses, std::make_unique<Ekf>(s.calibration, s.config),
             std::make_unique<Ekf>(s.calibration, s.config)};
  return *oldest;
}

// active_dim, which check_filter bounds by the pool after every operation, within kMaxActiveDim.
int bounded_active_dim(const Ekf& e) {
  const int n = e.active_dim();
  if (n < 0 || n > kMaxActiveDim) {
    std::fprintf(stderr, "fuzz_ekf: active_dim %d beyond the largest pool's %d\n", n,
                 kMaxActiveDim);
    std::abort();
  }
  return n;
}

struct Snapshot {
  ActiveVector x;
  ActiveMatrix P;
  int landmarks = 0;
};

Snapshot snapshot(const Ekf& e) {
  const int n = bounded_active_dim(e);
  return {e.state().head(n), e.covariance().topLeftCorner(n, n), e.landmark_count()};
}

bool unchanged(const Snapshot& s, const Ekf& e) {
  const int n = e.active_dim();
  return n == s.x.size() && e.landmark_count() == s.landmarks && s.x == e.state().head(n) &&
         s.P == e.covariance().topLeftCorner(n, n);
}

std::uint64_t rejections(const Ekf& e) {
  std::uint64_t sum = 0;
  for (const std::uint64_t r : e.counters().rejections.by_reason) {
    sum += r;
  }
  return sum;
}

// Smallest eigenvalue of A at least -kPsdTolerance times the larger of A's largest eigenvalue
// magnitude and scale. Rounding in a covariance is relative to the largest variance it has held,
// and stays when a landmark of that variance leaves the state: scale is that largest variance.
// A + s I with s = kPsdTolerance max(max|A_ii|, scale) (at most kPsdTolerance times that larger
// magnitude) has a Cholesky factor only when every eigenvalue of A is above -s, so that factor,
// several times cheaper, settles most cases; the eigenvalues decide the rest.
template <typename Matrix>
bool positive_semidefinite(const Matrix& A, double scale) {
  double diagonal = scale;
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    diagonal = std::max(diagonal, std::abs(A(i, i)));
  }
  if (diagonal <= 0.0) {
    return true;
  }
  Matrix shifted = A;
  shifted.diagonal().array() += kPsdTolerance * diagonal;
  if (Eigen::LLT<Matrix>(shifted).info() == Eigen::Success) {
    return true;
  }
  const Eigen::VectorXd eigenvalues = cleanslam::test::symmetric_eigenvalues(A);
  const double magnitude = std::max(eigenvalues.cwiseAbs().maxCoeff(), scale);
  return eigenvalues.minCoeff() >= -kPsdTolerance * magnitude;
}

enum class Op : std::uint8_t {
  kPredict,
  kInitialize,
  kInitializeAtDepth,
  kUpdate,
  kDelete,
  kMerge,
  kSetUpdateStep,
  kContinueUpdate,
  kFinishUpdate,
  kPredictPixel,
  kJointPixelInnovation,
  kBodyPose,
  kReset,
  kCount
};
constexpr std::array<const char*, static_cast<std::size_t>(Op::kCount)> kOpNames{
    "predict",
    "initialize_landmark",
    "initialize_landmark(depth)",
    "update",
    "delete_landmark",
    "merge_landmarks",
    "set_update_step",
    "continue_update",
    "finish_update",
    "predict_pixel",
    "joint_pixel_innovation",
    "body_pose_estimate",
    "reset"};
// Opcodes from here on corrupt one input of their operation.
constexpr std::uint8_t kFirstHostileOpcode = 224;

class Session {
 public:
  Session(ByteReader& in, const Setup& s, Ekf& chunked, Ekf& one_shot)
      : in_(in), filter_(chunked), one_shot_(one_shot) {
    filter_.set_update_step(0);
    one_shot_.set_update_step(0);
    max_slots_ = s.config.max_landmarks;
    widest_ = std::max(filter_.active_dim(), one_shot_.active_dim());
    reset(false);
  }

  void run() {
    while (!in_.done() && operation_ < kMaxOperations) {
      const std::uint8_t code = in_.byte();
      const auto op = static_cast<Op>(code % static_cast<int>(Op::kCount));
      ++operation_;
      name_ = kOpNames[static_cast<std::size_t>(op)];
      dispatch(op, code >= kFirstHostileOpcode);
      widest_ = std::max({widest_, filter_.active_dim(), one_shot_.active_dim()});
      note_largest_variance();
      check_filter();
      compare_with_one_shot();
    }
    ++operation_;
    name_ = "finish_update (end of input)";
    settle();
    check_filter();
    compare_with_one_shot();
    check_psd();
    expect(zero_beyond_active_dim(filter_) && zero_beyond_active_dim(one_shot_),
           "x or P not zero beyond active_dim");
  }

 private:
  struct PendingUpdate {
    Snapshot before;
    std::uint64_t rejections = 0;
    int count = 0;
  };

  [[noreturn]] void fail(const char* invariant) const {
    std::fprintf(stderr, "fuzz_ekf: %s, after operation %d (%s)\n", invariant, operation_, name_);
    std::abort();
  }
  void expect(bool ok, const char* invariant) const {
    if (!ok) {
      fail(invariant);
    }
  }

  void dispatch(Op op, bool hostile) {
    switch (op) {
      case Op::kPredict:
        predict(hostile);
        break;
      case Op::kInitialize:
        initialize(false, hostile);
        break;
      case Op::kInitializeAtDepth:
        initialize(true, hostile);
        break;
      case Op::kUpdate:
        update(hostile);
        break;
      case Op::kDelete:
        delete_landmark();
        break;
      case Op::kMerge:
        merge(hostile);
        break;
      case Op::kSetUpdateStep:
        set_update_step(hostile);
        break;
      case Op::kContinueUpdate:
        continue_update();
        break;
      case Op::kFinishUpdate:
        settle();
        break;
      case Op::kPredictPixel:
        predict_pixel();
        break;
      case Op::kJointPixelInnovation:
        joint_pixel_innovation(hostile);
        break;
      case Op::kBodyPose:
        body_pose();
        break;
      case Op::kReset:
      case Op::kCount:
        reset(hostile);
        break;
    }
  }

  // A used slot mostly; otherwise a free, reserved or out-of-range one.
  int pick_slot() {
    constexpr std::array kOdd{-1,      0,      1, 12, hal::kMaxLandmarks - 1, hal::kMaxLandmarks,
                              INT_MIN, INT_MAX};
    const std::uint8_t b = in_.byte();
    if (b >= 200) {
      const auto odd = static_cast<std::size_t>(b - 200);
      return odd < kOdd.size() ? kOdd[odd] : b - 200 - static_cast<int>(kOdd.size());
    }
    const int count = filter_.landmark_count();
    int k = count > 0 ? b % count : -1;
    const auto& used = filter_.used_mask();
    for (int s = 0; s < hal::kMaxLandmarks; ++s) {
      if (used[static_cast<std::size_t>(s)] && k-- == 0) {
        return s;
      }
    }
    return b % 16;
  }

  // Near the predicted pixel mostly; count < 0 gives none.
  std::vector<Observation> observations(int count, bool hostile) {
    std::vector<Observation> obs(static_cast<std::size_t>(std::max(count, 0)));
    for (Observation& o : obs) {
      o.slot = pick_slot();
      PixelPrediction p;
      if (in_.byte() < 200 && filter_.predict_pixel(o.slot, p)) {
        o.u_px = p.uv.x() + in_.range(-4.0, 4.0);
        o.v_px = p.uv.y() + in_.range(-4.0, 4.0);
      } else {
        o.u_px = in_.range(-20.0, 340.0);
        o.v_px = in_.range(-20.0, 260.0);
      }
    }
    if (hostile && !obs.empty()) {
      Observation& o = obs[in_.byte() % obs.size()];
      in_.corrupt({field(o.u_px), field(o.v_px)});
    }
    return obs;
  }

  void reset(bool hostile) {
    Vector6d pose;
    pose(0) = in_.range(-5.0, 5.0);
    pose(1) = in_.range(-5.0, 5.0);
    pose(2) = in_.range(-0.5, 0.5);
    pose(3) = in_.range(-0.3, 0.3);
    pose(4) = in_.range(-1.5, 1.5);
    pose(5) = in_.range(-std::numbers::pi, std::numbers::pi);
    Matrix6d P0 = covariance(in_, -4.0, -0.5);
    if (hostile) {
      in_.corrupt({field(pose), field(P0)});
    }
    const Snapshot before = snapshot(filter_);
    const bool done = filter_.reset(pose, P0);
    expect(one_shot_.reset(pose, P0) == done, "reset: the two filters disagree");
    expect(done || hostile, "reset: a finite pose and a PSD covariance refused");
    if (done) {
      pending_.reset();
      largest_variance_ = 0.0;
      note_largest_variance();
      expect(filter_.landmark_count() == 0 && !filter_.update_pending(),
             "reset: the map or an update left");
    } else {
      expect(unchanged(before, filter_), "reset: refused, but the filter changed");
    }
  }

  // Completes a pending update and checks its outcome.
  void settle() {
    filter_.finish_update();
    check_update();
  }

  void check_update() {
    if (!pending_ || filter_.update_pending()) {
      return;
    }
    const auto& st = filter_.last_update();
    expect(st.fused + st.rejected == pending_->count,
           "update: fused + rejected differs from the observations given");
    expect(st.applied == (st.fused > 0), "update: applied differs from fused > 0");
    expect(rejections(filter_) - pending_->rejections == static_cast<std::uint64_t>(st.rejected),
           "update: rejections not counted");
    expect(st.applied || unchanged(pending_->before, filter_),
           "update: state changed though nothing was fused");
    pending_.reset();
    check_psd();
  }

  void predict(bool hostile) {
    settle();
    OdometryIncrement u;
    u.dx_c.x() = in_.range(-0.1, 0.3);
    u.dx_c.y() = in_.range(-0.05, 0.05);
    u.dx_c.z() = in_.range(-0.02, 0.02);
    u.dpsi_c.x() = in_.range(-0.05, 0.05);
    u.dpsi_c.y() = in_.range(-0.05, 0.05);
    u.dpsi_c.z() = in_.range(-0.4, 0.4);
    u.Q = covariance(in_, -5.0, -1.5);
    u.dt_s = in_.range(0.0, 2.0);
    u.distance_m = u.dx_c.norm();
    if (hostile) {
      in_.corrupt({field(u.dx_c), field(u.dpsi_c), field(u.Q), field(u.dt_s)});
    }
    const Snapshot before = snapshot(filter_);
    const std::uint64_t refused = filter_.counters().predictions_rejected;
    const auto result = filter_.predict(u).result;
    one_shot_.predict(u);
    if (!u.dx_c.allFinite() || !u.dpsi_c.allFinite() || !u.Q.allFinite()) {
      expect(result == PredictResult::kNonFinite, "predict: non-finite increment not refused");
    }
    const int n = filter_.active_dim();
    if (result != PredictResult::kApplied) {
      expect(unchanged(before, filter_), "predict: refused but changed the state");
      expect(filter_.counters().predictions_rejected == refused + 1,
             "predict: refusal not counted");
    } else {
      const int map = hal::kPoseDim;
      expect(n == before.x.size() &&
                 before.x.tail(n - map) == filter_.state().segment(map, n - map) &&
                 before.P.bottomRightCorner(n - map, n - map) ==
                     filter_.covariance().block(map, map, n - map, n - map),
             "predict: changed the map");
      check_psd();
    }
  }

  void initialize(bool at_depth, bool hostile) {
    settle();
    double u = in_.range(-10.0, 330.0);
    double v = in_.range(-10.0, 250.0);
    double depth = in_.log_range(-1.5, 1.5);
    double eps_ct = in_.log_range(-2.0, 3.0);
    if (hostile && at_depth) {
      in_.corrupt({field(u), field(v), field(depth), field(eps_ct)});
    } else if (hostile) {
      in_.corrupt({field(u), field(v)});
    }
    const Snapshot before = snapshot(filter_);
    const std::uint64_t rejected = rejections(filter_);
    const int slot = at_depth ? filter_.initialize_landmark(u, v, depth, eps_ct)
                              : filter_.initialize_landmark(u, v);
    const int slot2 = at_depth ? one_shot_.initialize_landmark(u, v, depth, eps_ct)
                               : one_shot_.initialize_landmark(u, v);
    expect(slot == slot2, "initialize_landmark: chunked and one-shot filters chose other slots");
    if (slot < 0) {
      expect(unchanged(before, filter_), "initialize_landmark: refused but changed the state");
      expect(rejections(filter_) == rejected + 1, "initialize_landmark: refusal not counted");
      return;
    }
    expect(std::isfinite(u) && std::isfinite(v) &&
               (!at_depth || (std::isfinite(depth) && std::isfinite(eps_ct))),
           "initialize_landmark: accepted a non-finite input");
    expect(filter_.slot_used(slot) && slot >= 0 && slot < max_slots_,
           "initialize_landmark: returned a slot outside the pool");
    check_psd();
  }

  void update(bool hostile) {
    settle();
    const int count = in_.byte() % (hal::kMaxObservationsPerFrame + 3);
    const std::vector<Observation> obs = observations(count, hostile);
    pending_ = PendingUpdate{snapshot(filter_), rejections(filter_), count};
    filter_.update(obs.data(), count);
    one_shot_.update(obs.data(), count);
    check_update();
  }

  void continue_update() {
    const int calls = 1 + in_.byte() % 8;
    for (int i = 0; i < calls; ++i) {
      if (filter_.continue_update()) {
        check_update();
        return;
      }
    }
  }

  void delete_landmark() {
    settle();
    const int slot = pick_slot();
    const bool used = filter_.slot_used(slot);
    const Snapshot before = snapshot(filter_);
    filter_.delete_landmark(slot);
    one_shot_.delete_landmark(slot);
    if (used) {
      expect(!filter_.slot_used(slot) && filter_.landmark_count() == before.landmarks - 1,
             "delete_landmark: slot still used");
    } else {
      expect(unchanged(before, filter_), "delete_landmark: unused slot changed the state");
    }
  }

  void merge(bool hostile) {
    settle();
    const int keep = pick_slot();
    const int drop = pick_slot();
    constexpr std::array kGates{0.0, 7.81, 11.34, 1e9};
    double gate = kGates[in_.byte() % kGates.size()];
    double merge_std = in_.range(0.0, 0.3);
    if (hostile) {
      in_.corrupt({field(gate), field(merge_std)});
    }
    const bool valid = filter_.slot_used(keep) && filter_.slot_used(drop) && keep != drop;
    const Snapshot before = snapshot(filter_);
    const ObservationResult r = filter_.merge_landmarks(keep, drop, gate, merge_std);
    one_shot_.merge_landmarks(keep, drop, gate, merge_std);
    expect(valid || r == ObservationResult::kInvalidSlot, "merge_landmarks: invalid slots merged");
    if (r == ObservationResult::kFused) {
      expect(!filter_.slot_used(drop) && filter_.slot_used(keep) &&
                 filter_.landmark_count() == before.landmarks - 1,
             "merge_landmarks: dropped slot still used");
      check_psd();
    } else {
      expect(unchanged(before, filter_), "merge_landmarks: refused but changed the state");
    }
  }

  void set_update_step(bool hostile) {
    const std::uint8_t b = in_.byte();
    std::int64_t work = b < 64 ? 0 : std::int64_t{1} << (b % 28);
    if (hostile) {
      const double d = in_.raw();
      std::memcpy(&work, &d, sizeof work);
    }
    filter_.set_update_step(work);
    expect(filter_.update_step() >= 0, "set_update_step: negative budget kept");
  }

  void predict_pixel() {
    const int slot = pick_slot();
    PixelPrediction p;
    if (!filter_.predict_pixel(slot, p)) {
      return;
    }
    expect(filter_.slot_used(slot) && p.in_front && p.depth_m > 0.0,
           "predict_pixel: prediction of an unused slot or behind the camera");
    expect(p.uv.allFinite() && p.S.allFinite(), "predict_pixel: not finite");
    const double r = filter_.config().eps_trk_px * filter_.config().eps_trk_px +
                     filter_.config().eps_cal_px * filter_.config().eps_cal_px;
    const double tolerance =
        kPsdTolerance * (1.0 + p.S.cwiseAbs().maxCoeff()) + pixel_rounding(slot);
    expect(p.S(0, 1) == p.S(1, 0), "predict_pixel: S not symmetric");
    if (!filter_.update_pending()) {
      expect(cleanslam::test::min_eigenvalue(p.S) >= r - tolerance, "predict_pixel: S below R_pix");
    }
  }

  // The rounding error of J P J^T in a landmark's pixel covariance: its terms are the variances it
  // projects, in pixels (the landmark's along the ray reach eps_ct^2), while the sum may be near
  // R_pix. J grows as focal / depth and, through the distortion, up to |n|^4 off the axis. P's own
  // rounding, which positive_semidefinite bounds by the largest variance P has held, adds its
  // projection.
  double pixel_rounding(int slot) const {
    PixelPrediction p;
    if (!filter_.predict_pixel(slot, p)) {
      return 0.0;
    }
    const auto& camera = filter_.camera();
    const Eigen::Vector2d centre(0.5 * camera.width(), 0.5 * camera.height());
    const double n2 = ((p.uv - centre) / camera.focal_px()).squaredNorm();
    const double f = camera.focal_px() / p.depth_m;
    const double lever = (filter_.landmark(slot) - filter_.camera_pose().head<3>()).norm();
    const double variance = filter_.landmark_covariance(slot).cwiseAbs().maxCoeff() +
                            filter_.pose_covariance().cwiseAbs().maxCoeff() * (1.0 + lever * lever);
    return f * f * std::pow(1.0 + n2, 4.0) *
           (1e3 * std::numeric_limits<double>::epsilon() * variance +
            kPsdTolerance * largest_variance_ * (2.0 + lever * lever));
  }

  void joint_pixel_innovation(bool hostile) {
    const int count = in_.byte() % (hal::kMaxObservationsPerFrame + 3) - 1;
    const std::vector<Observation> obs = observations(count, hostile);
    const auto m = static_cast<std::size_t>(std::max(count, 0));
    // A hostile caller's buffers may be an entry short; a guard entry follows each. Which is short
    // comes from the first slot, so that the corpus' inputs read the same bytes as before.
    const std::size_t shorten =
        hostile && !obs.empty() ? static_cast<std::size_t>(obs.front().slot) % 4 : 0;
    const std::size_t short_nu = shorten & 1U;
    const std::size_t short_S = (shorten >> 1U) & 1U;
    constexpr double kGuard = -12345.0;
    std::vector<double> nu(2 * m + 1, kGuard);
    std::vector<double> S(4 * m * m + 1, kGuard);
    const std::size_t nu_size = 2 * m - std::min(short_nu, 2 * m);
    const std::size_t S_size = 4 * m * m - std::min(short_S, 4 * m * m);
    const int r = filter_.joint_pixel_innovation(obs, std::span<double>(nu).first(nu_size),
                                                 std::span<double>(S).first(S_size));
    expect(nu[nu_size] == kGuard && S[S_size] == kGuard,
           "joint_pixel_innovation: wrote past the caller's buffers");
    const bool fits = nu_size == 2 * m && S_size == 4 * m * m;
    expect(fits || m == 0 || r == -1, "joint_pixel_innovation: took buffers too small");
    expect(r == -1 || r == static_cast<int>(obs.size()),
           "joint_pixel_innovation: returned neither -1 nor the count");
    if (r <= 0) {
      return;
    }
    const auto dim = static_cast<Eigen::Index>(2 * m);
    const Eigen::Map<const Eigen::MatrixXd> Sm(S.data(), dim, dim);
    expect(Sm.allFinite(), "joint_pixel_innovation: S not finite");
    expect(Sm == Sm.transpose(), "joint_pixel_innovation: S not symmetric");
    expect(Eigen::Map<const Eigen::VectorXd>(nu.data(), dim).allFinite(),
           "joint_pixel_innovation: innovation not finite");
    if (!filter_.update_pending()) {
      const double r_pix = filter_.config().eps_trk_px * filter_.config().eps_trk_px +
                           filter_.config().eps_cal_px * filter_.config().eps_cal_px;
      const Eigen::VectorXd eigenvalues = cleanslam::test::symmetric_eigenvalues(Sm);
      double rounding = 0.0;
      for (const Observation& o : obs) {
        rounding += pixel_rounding(o.slot);
      }
      expect(eigenvalues.minCoeff() >=
                 r_pix - kPsdTolerance * (1.0 + Sm.cwiseAbs().maxCoeff()) - rounding,
             "joint_pixel_innovation: S below R_pix");
    }
  }

  void body_pose() {
    const hal::PoseEstimate est = filter_.body_pose_estimate(0);
    const Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> C(est.covariance.data());
    const Eigen::Map<const Eigen::Vector4d> q(est.orientation_wxyz.data());
    expect(Eigen::Map<const Eigen::Vector3d>(est.position_m.data()).allFinite() && q.allFinite() &&
               C.allFinite(),
           "body_pose_estimate: not finite");
    expect(std::abs(q.norm() - 1.0) < 1e-9, "body_pose_estimate: quaternion not unit");
    expect(C == C.transpose(), "body_pose_estimate: covariance not symmetric");
    expect(est.landmarks_in_map == filter_.landmark_count(),
           "body_pose_estimate: landmark count differs");
  }

  // Past active_dim, up to the widest state this filter had since its previous input (the rest was
  // checked then, or never active): reset clears only the active block.
  bool zero_beyond_active_dim(const Ekf& e) const {
    const int n = e.active_dim();
    const auto pool_dim = static_cast<int>(e.state().size());
    const int above = std::max(std::min(hal::kLandmarkDim, pool_dim - n), widest_ - n);
    return e.state().tail(pool_dim - n).isZero(0.0) &&
           e.covariance().middleRows(n, above).leftCols(n + above).isZero(0.0) &&
           e.covariance().middleCols(n, above).topRows(n + above).isZero(0.0);
  }

  void note_largest_variance() {
    const int n = bounded_active_dim(filter_);
    largest_variance_ =
        std::max(largest_variance_, filter_.covariance().diagonal().head(n).cwiseAbs().maxCoeff());
  }

  void check_filter() const {
    const Ekf& e = filter_;
    int highest = -1;
    int used = 0;
    const auto& used_mask = e.used_mask();
    for (int s = 0; s < hal::kMaxLandmarks; ++s) {
      if (used_mask[static_cast<std::size_t>(s)]) {
        expect(s < max_slots_, "landmark in an excess slot");
        highest = s;
        ++used;
      }
    }
    expect(used == e.landmark_count(), "landmark_count differs from the used slots");
    const int n = e.active_dim();
    expect(n == hal::kPoseDim + hal::kLandmarkDim * (highest + 1),
           "active_dim differs from the highest used slot");
    const auto x = e.state().head(n);
    const auto P = e.covariance().topLeftCorner(n, n);
    expect(x.allFinite(), "x not finite");
    expect(P.allFinite(), "P not finite");
    // P == P^T: the diagonal equals itself, P being finite.
    for (int j = 0; j < n; ++j) {
      for (int i = j + 1; i < n; ++i) {
        expect(P(i, j) == P(j, i), "P not symmetric");
      }
    }
    // Row i of the symmetric P is its column i, which is contiguous.
    for (int i = 0; i < n; ++i) {
      const int slot = (i - hal::kPoseDim) / hal::kLandmarkDim;
      const bool live = i < hal::kPoseDim || used_mask[static_cast<std::size_t>(slot)];
      if (!live) {
        expect(x(i) == 0.0 && P.col(i).isZero(0.0), "row of an unused slot not zero");
      } else {
        expect(P(i, i) >= -kPsdTolerance * P.col(i).cwiseAbs().maxCoeff(),
               "negative variance on the diagonal of P");
      }
    }
    expect(positive_semidefinite(Matrix6d(P.topLeftCorner<6, 6>()), largest_variance_),
           "pose block of P not positive semi-definite");
  }

  // After each change of P that is not an update in progress.
  void check_psd() const {
    const int n = bounded_active_dim(filter_);
    expect(positive_semidefinite(ActiveMatrix(filter_.covariance().topLeftCorner(n, n)),
                                 largest_variance_),
           "P not positive semi-definite");
  }

  void compare_with_one_shot() const {
    if (filter_.update_pending()) {
      return;
    }
    const int n = filter_.active_dim();
    expect(one_shot_.active_dim() == n && one_shot_.used_mask() == filter_.used_mask(),
           "chunked and one-shot filters hold other landmarks");
    expect(
        one_shot_.state().head(n) == filter_.state().head(n) &&
            one_shot_.covariance().topLeftCorner(n, n) == filter_.covariance().topLeftCorner(n, n),
        "chunked and one-shot filters differ in x or P");
  }

  ByteReader& in_;
  Ekf& filter_;    // updates with the step budget of set_update_step
  Ekf& one_shot_;  // every update at once
  int max_slots_ = 0;
  int widest_ = 0;  // the largest active_dim of either filter in this input or before its reset
  double largest_variance_ = 0.0;  // the largest variance of P since its last reset
  std::optional<PendingUpdate> pending_;
  int operation_ = 0;
  const char* name_ = "reset";
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ByteReader in(data, size);
  const Setup setup = read_setup(in);
  Filters& filters = filters_for(setup);
  Session session(in, setup, *filters.chunked, *filters.one_shot);
  session.run();
  return 0;
}
