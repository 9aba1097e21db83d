#include <cmath>
#include <fstream>
#include <string>

#include "cleanslam/evaluation/evaluation.hpp"
#include "cleanslam/readers/bounded_file.hpp"
#include "cleanslam/readers/csv.hpp"

namespace cleanslam::evaluation {
namespace {

// Splits on spaces, tabs and commas.
void split_fields(const std::string& line, std::vector<std::string_view>& out) {
  out.clear();
  const std::string_view s(line);
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == ',' || s[i] == '\r')) {
      ++i;
    }
    const std::size_t start = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t' && s[i] != ',' && s[i] != '\r') {
      ++i;
    }
    if (i > start) {
      out.push_back(s.substr(start, i - start));
    }
  }
}

std::string where(const std::string& path, int line) {
  return path + ":" + std::to_string(line) + ": ";
}

// Reads the numbers of one line; false with `error` set on a bad field.
bool numbers(const std::vector<std::string_view>& fields, const std::string& at,
             std::vector<double>& out, std::string& error) {
  out.clear();
  for (std::size_t i = 0; i < fields.size(); ++i) {
    double v = 0.0;
    if (!readers::parse_finite_double(fields[i], v)) {
      error = at + "field " + std::to_string(i + 1) + ": expected a finite number, got \"" +
              std::string(fields[i]) + "\"";
      return false;
    }
    out.push_back(v);
  }
  return true;
}

}  // namespace

readers::Result<std::vector<TumPose>> read_tum(const std::string& path) {
  using R = readers::Result<std::vector<TumPose>>;
  if (const readers::Status s = readers::check_bounded_file(path, readers::kTrajectoryFileLimit);
      !s) {
    return R::failure(s.error());
  }
  std::ifstream in(path);
  if (!in) {
    return R::failure(path + ": cannot open file");
  }
  std::vector<TumPose> out;
  std::string line, error;
  std::vector<std::string_view> fields;
  std::vector<double> v;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    split_fields(line, fields);
    if (fields.empty() || fields[0].front() == '#') {
      continue;
    }
    const std::string at = where(path, n);
    if (fields.size() != 8) {
      return R::failure(at + "expected 8 fields (t x y z qx qy qz qw), got " +
                        std::to_string(fields.size()));
    }
    if (!numbers(fields, at, v, error)) {
      return R::failure(error);
    }
    TumPose p;
    p.t_ns = static_cast<hal::TimeNs>(std::llround(v[0] * 1e9));
    if (!out.empty() && p.t_ns <= out.back().t_ns) {
      return R::failure(at + "t: time stamps must increase");
    }
    p.position = {v[1], v[2], v[3]};
    const double qn = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (qn < 0.5 || qn > 1.5) {
      return R::failure(at + "quaternion norm " + readers::format_double(qn) + " is not about 1");
    }
    p.orientation_wxyz = {v[7] / qn, v[4] / qn, v[5] / qn, v[6] / qn};
    out.push_back(p);
  }
  if (out.empty()) {
    return R::failure(path + ": no poses");
  }
  return out;
}

readers::Status read_covariances(const std::string& path, std::vector<TumPose>& poses) {
  if (readers::Status s = readers::check_bounded_file(path, readers::kTrajectoryFileLimit); !s) {
    return s;
  }
  std::ifstream in(path);
  if (!in) {
    return readers::Status::failure(path + ": cannot open file");
  }
  std::string line, error;
  std::vector<std::string_view> fields;
  std::vector<double> v;
  int n = 0;
  std::size_t k = 0;
  while (std::getline(in, line)) {
    ++n;
    split_fields(line, fields);
    if (fields.empty() || fields[0].front() == '#') {
      continue;
    }
    const std::string at = where(path, n);
    if (fields.size() != 10 && fields.size() != 37) {
      return readers::Status::failure(
          at + "expected t and 9 (3x3) or 36 (6x6) covariance entries, got " +
          std::to_string(fields.size()) + " fields");
    }
    if (!numbers(fields, at, v, error)) {
      return readers::Status::failure(error);
    }
    const auto t = static_cast<hal::TimeNs>(std::llround(v[0] * 1e9));
    while (k < poses.size() && poses[k].t_ns < t - 1000) {
      ++k;
    }
    if (k >= poses.size() || std::llabs(poses[k].t_ns - t) > 1000) {
      return readers::Status::failure(at + "t: no pose with this time stamp in the TUM file");
    }
    std::array<double, 9> c{};
    const std::size_t stride = fields.size() == 10 ? 3 : 6;
    for (std::size_t r = 0; r < 3; ++r) {
      for (std::size_t col = 0; col < 3; ++col) {
        c[3 * r + col] = v[1 + r * stride + col];
      }
    }
    poses[k].position_covariance = c;
  }
  return readers::Status();
}

}  // namespace cleanslam::evaluation
