#include "cleanslam/firmware/sinks.hpp"

#include <cerrno>
#include <cstring>

namespace cleanslam::firmware {

namespace {

using Quat = std::array<double, 4>;  // w x y z

Quat conjugate(const Quat& q) {
  return {q[0], -q[1], -q[2], -q[3]};
}
Quat multiply(const Quat& a, const Quat& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}
// Rotation matrix of a unit quaternion, row-major.
std::array<double, 9> matrix(const Quat& q) {
  const double w = q[0];
  const double x = q[1];
  const double y = q[2];
  const double z = q[3];
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

}  // namespace

bool TumWriter::open(const std::string& path, bool relative_to_first, bool with_covariance,
                     std::string& error, Rotation rotation) {
  (void)close();
  relative_ = relative_to_first;
  have_first_ = false;
  if (!file_.open(path, rotation, error)) {
    return false;
  }
  return !with_covariance || cov_.open(path + ".cov", rotation, error);
}

void TumWriter::publish(const hal::PoseEstimate& pose) {
  if (!file_.is_open()) {
    return;
  }
  if (file_.full() || cov_.full()) {
    file_.rotate(nullptr);
    cov_.rotate(nullptr);
  }
  std::array<double, 3> p = pose.position_m;
  Quat q = pose.orientation_wxyz;
  std::array<double, 36> cov = pose.covariance;
  if (relative_) {
    if (!have_first_) {
      p0_ = p;
      q0_ = q;
      have_first_ = true;
    }
    // T_rel = T_0^-1 T: p_rel = R0^T (p - p0), q_rel = q0* q; position covariance R0^T S R0.
    const auto R0 = matrix(q0_);
    const std::array<double, 3> d{p[0] - p0_[0], p[1] - p0_[1], p[2] - p0_[2]};
    for (std::size_t i = 0; i < 3; ++i) {
      p[i] =
          R0[i] * d[0] + R0[3 + i] * d[1] + R0[6 + i] * d[2];  // row-major: R0(k, i) = R0[3k + i]
    }
    q = multiply(conjugate(q0_), q);
    // J = blockdiag(R0^T, I3): cov' = J cov J^T.
    std::array<double, 36> J{};
    for (std::size_t i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < 3; ++j) {
        J[i * 6 + j] = R0[j * 3 + i];
      }
      J[(i + 3) * 6 + i + 3] = 1.0;
    }
    std::array<double, 36> tmp{};
    for (std::size_t i = 0; i < 6; ++i) {
      for (std::size_t j = 0; j < 6; ++j) {
        double s = 0.0;
        for (std::size_t k = 0; k < 6; ++k) {
          s += J[i * 6 + k] * pose.covariance[k * 6 + j];
        }
        tmp[i * 6 + j] = s;
      }
    }
    for (std::size_t i = 0; i < 6; ++i) {
      for (std::size_t j = 0; j < 6; ++j) {
        double s = 0.0;
        for (std::size_t k = 0; k < 6; ++k) {
          s += tmp[i * 6 + k] * J[j * 6 + k];
        }
        cov[i * 6 + j] = s;
      }
    }
  }
  const double t = static_cast<double>(pose.t_ns) * 1e-9;
  file_.print("%.9f %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", t, p[0], p[1], p[2], q[1], q[2], q[3],
              q[0]);
  if (cov_.is_open()) {
    cov_.print("%.9f", t);
    for (double v : cov) {
      cov_.print(" %.9g", v);
    }
    cov_.print("\n");
  }
}

void TumWriter::flush() {
  file_.flush();
  cov_.flush();
}

bool TumWriter::close() {
  const bool file_ok = file_.close();
  const bool cov_ok = cov_.close();
  return file_ok && cov_ok;
}

std::vector<std::string> TumWriter::errors() const {
  std::vector<std::string> out;
  for (const RotatingFile* f : {&file_, &cov_}) {
    if (f->failed()) {
      out.push_back(f->error());
    }
  }
  return out;
}

const char* to_string(hal::log::UpdateStatus s) {
  switch (s) {
    case hal::log::UpdateStatus::kUpdated:
      return "updated";
    case hal::log::UpdateStatus::kInitialized:
      return "initialized";
    case hal::log::UpdateStatus::kGated:
      return "gated";
    case hal::log::UpdateStatus::kRejected:
      return "rejected";
    case hal::log::UpdateStatus::kSkipped:
      return "skipped";
    case hal::log::UpdateStatus::kNoSlot:
      return "no_slot";
    case hal::log::UpdateStatus::kMerged:
      return "merged";
    case hal::log::UpdateStatus::kMergeGated:
      return "merge_gated";
    case hal::log::UpdateStatus::kDepthBound:
      return "depth_bound";
    case hal::log::UpdateStatus::kBehindCamera:
      return "behind_camera";
  }
  return "?";
}

bool CsvSink::open_with_header(const std::string& path, const char* header, std::string& error,
                               Rotation rotation) {
  header_ = header;
  if (!file_.open(path, rotation, error)) {
    return false;
  }
  file_.print("%s", header);
  return true;
}

RotatingFile& CsvSink::row() {
  if (file_.full()) {
    file_.rotate(header_);
  }
  return file_;
}

void CsvSink::flush() {
  file_.flush();
}

bool DiagnosticsCsv::open(const std::string& path, std::string& error, Rotation rotation) {
  return open_with_header(
      path, "#t_ns,track_id,slot,status,u_px,v_px,innovation_u,innovation_v,mahalanobis2\n", error,
      rotation);
}

void DiagnosticsCsv::update(const hal::log::UpdateRecord& r) {
  if (!file().is_open()) {
    return;
  }
  row().print("%lld,%lld,%d,%s,%.9g,%.9g,%.9g,%.9g,%.9g\n", static_cast<long long>(r.t_ns),
              static_cast<long long>(r.track_id), r.slot, to_string(r.status), r.u_px, r.v_px,
              r.innovation_u, r.innovation_v, r.mahalanobis2);
}

}  // namespace cleanslam::firmware
