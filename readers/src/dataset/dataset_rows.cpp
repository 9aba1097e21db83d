#include <cmath>
#include <limits>

#include "row_reader.hpp"

namespace cleanslam::readers {
namespace {

// Each file's columns, order of its stamps and fields after the stamp (read_fields fills all but
// t_ns and returns an error message or nothing).
template <typename Row>
struct RowFormat;

// Tick counts are 32-bit counters; values written as unsigned (up to 2^32 - 1) wrap.
std::string read_ticks(const CsvRow& row, std::size_t i, std::int32_t& out) {
  auto v = row.integer(i);
  if (!v.ok()) {
    return v.error();
  }
  if (*v < std::numeric_limits<std::int32_t>::min() ||
      *v > static_cast<std::int64_t>(std::numeric_limits<std::uint32_t>::max())) {
    return row.fail(i, std::to_string(*v) + " does not fit a 32-bit counter");
  }
  out = static_cast<std::int32_t>(static_cast<std::uint32_t>(*v));
  return {};
}

template <>
struct RowFormat<hal::GyroSample> {
  static CsvSpec spec() { return {{"t_ns", "wz_rad_s"}, {"wx_rad_s", "wy_rad_s"}}; }
  static constexpr bool kStrictlyIncreasing = true;
  static std::string read_fields(const CsvRow& row, std::size_t index, hal::GyroSample& g) {
    auto wz = row.number(1);
    if (!wz.ok()) {
      return wz.error();
    }
    g.wz_rad_s = *wz;
    g.wx_rad_s = 0.0;
    g.wy_rad_s = 0.0;
    g.has_xy = false;
    if (row.size() == 4) {
      auto wx = row.number(2);
      if (!wx.ok()) {
        return wx.error();
      }
      auto wy = row.number(3);
      if (!wy.ok()) {
        return wy.error();
      }
      g.wx_rad_s = *wx;
      g.wy_rad_s = *wy;
      g.has_xy = true;
    }
    g.seq = static_cast<std::uint32_t>(index);
    return {};
  }
};

template <>
struct RowFormat<hal::EncoderSample> {
  static CsvSpec spec() { return {{"t_ns", "left_ticks", "right_ticks"}, {}}; }
  static constexpr bool kStrictlyIncreasing = true;
  static std::string read_fields(const CsvRow& row, std::size_t index, hal::EncoderSample& e) {
    std::string err = read_ticks(row, 1, e.left_ticks);
    if (err.empty()) {
      err = read_ticks(row, 2, e.right_ticks);
    }
    e.seq = static_cast<std::uint32_t>(index);
    return err;
  }
};

template <>
struct RowFormat<CameraIndexRow> {
  static CsvSpec spec() { return {{"t_ns", "filename"}, {}}; }
  static constexpr bool kStrictlyIncreasing = true;
  static std::string read_fields(const CsvRow& row, std::size_t /*index*/, CameraIndexRow& c) {
    const std::string_view name = row.text(1);
    if (name.empty()) {
      return row.fail(1, "empty file name");
    }
    const bool parent = name == ".." || name.starts_with("../") || name.ends_with("/..") ||
                        name.find("/../") != std::string_view::npos;
    if (name.front() == '/' || parent) {
      return row.fail(
          1, "file name must be relative to cam0/data/, got \"" + std::string(name) + "\"");
    }
    c.filename.assign(name);
    c.line = row.line();
    return {};
  }
};

template <>
struct RowFormat<FeatureRow> {
  static CsvSpec spec() { return {{"t_ns", "track_id", "u_px", "v_px"}, {}}; }
  static constexpr bool kStrictlyIncreasing = false;  // the rows of a frame share its stamp
  static std::string read_fields(const CsvRow& row, std::size_t /*index*/, FeatureRow& f) {
    auto id = row.integer(1);
    if (!id.ok()) {
      return id.error();
    }
    if (*id < 0) {
      return row.fail(1, "track id must be non-negative");
    }
    auto u = row.number(2);
    if (!u.ok()) {
      return u.error();
    }
    auto v = row.number(3);
    if (!v.ok()) {
      return v.error();
    }
    f.observation = hal::FeatureObservation{*id, *u, *v};
    return {};
  }
};

template <>
struct RowFormat<GroundTruthPose> {
  static CsvSpec spec() { return {{"t_ns", "x_m", "y_m", "z_m", "qw", "qx", "qy", "qz"}, {}}; }
  static constexpr bool kStrictlyIncreasing = true;
  static std::string read_fields(const CsvRow& row, std::size_t /*index*/, GroundTruthPose& p) {
    double v[7];
    for (std::size_t i = 0; i < 7; ++i) {
      auto x = row.number(i + 1);
      if (!x.ok()) {
        return x.error();
      }
      v[i] = *x;
    }
    const double n = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
    if (std::abs(n - 1.0) > 1e-3) {
      return row.fail(4, "quaternion norm " + format_double(n) + " is not 1");
    }
    p.position_m = {v[0], v[1], v[2]};
    p.orientation_wxyz = {v[3] / n, v[4] / n, v[5] / n, v[6] / n};
    return {};
  }
};

template <>
struct RowFormat<LiftRow> {
  static CsvSpec spec() { return {{"t_ns", "lifted"}, {}}; }
  static constexpr bool kStrictlyIncreasing = true;
  static std::string read_fields(const CsvRow& row, std::size_t /*index*/, LiftRow& l) {
    auto v = row.integer(1);
    if (!v.ok()) {
      return v.error();
    }
    if (*v != 0 && *v != 1) {
      return row.fail(1, "expected 0 or 1, got " + std::to_string(*v));
    }
    l.lifted = *v == 1;
    return {};
  }
};

template <typename Row>
Result<std::vector<Row>> read_all(const std::string& path, const RowLimits& limits) {
  RowReader<Row> reader;
  Status s = reader.open(path, limits);
  if (!s) {
    return Result<std::vector<Row>>::failure(s.error());
  }
  std::vector<Row> out;
  Row row;
  while (reader.next(row)) {
    out.push_back(row);
  }
  if (!reader.error().empty()) {
    return Result<std::vector<Row>>::failure(reader.error());
  }
  return out;
}

}  // namespace

template <typename Row>
Status RowReader<Row>::open(const std::string& path, const RowLimits& limits) {
  limits_ = limits;
  previous_ = 0;
  span_end_ = 0;
  kept_ = 0;
  told_ = 0;
  error_.clear();
  CsvSpec spec = RowFormat<Row>::spec();
  spec.warnings = limits.warnings;
  return csv_.open(path, spec);
}

template <typename Row>
bool RowReader<Row>::next(Row& out) {
  while (const std::optional<CsvRow> row = csv_.next()) {
    auto t = row->integer(0);
    if (!t.ok()) {
      error_ = t.error();
      return false;
    }
    if (*t < 0) {
      error_ = row->fail(0, "negative time stamp " + std::to_string(*t));
      return false;
    }
    if (kept_ > 0 && (*t < previous_ || (RowFormat<Row>::kStrictlyIncreasing && *t == previous_))) {
      error_ =
          row->fail(0, "time stamp " + std::to_string(*t) + " is not after the previous row's " +
                           std::to_string(previous_) + " (rows must be sorted by time)");
      return false;
    }
    if (!within_span(*row, *t)) {
      continue;
    }
    out.t_ns = *t;
    error_ = RowFormat<Row>::read_fields(*row, kept_, out);
    if (!error_.empty()) {
      return false;
    }
    previous_ = *t;
    ++kept_;
    return true;
  }
  error_ = csv_.error();
  return false;
}

template <typename Row>
bool RowReader<Row>::within_span(const CsvRow& row, hal::TimeNs t) {
  if (kept_ == 0) {
    span_end_ = hal::add_saturated(t, limits_.max_span_ns);
  }
  if (t <= span_end_) {
    return true;
  }
  if (limits_.refused != nullptr) {
    ++*limits_.refused;
  }
  if (limits_.warnings != nullptr && ++told_ <= kMaxTold) {
    limits_.warnings->push_back(row.fail(
        0,
        "time stamp " + std::to_string(t) + " is more than " +
            format_double(hal::to_seconds(limits_.max_span_ns)) +
            " s (loop.max_span_s) after the file's first row: row refused" +
            (told_ == kMaxTold ? " (later ones of this file are refused without a message)" : "")));
  }
  return false;
}

template class RowReader<hal::GyroSample>;
template class RowReader<hal::EncoderSample>;
template class RowReader<CameraIndexRow>;
template class RowReader<FeatureRow>;
template class RowReader<GroundTruthPose>;
template class RowReader<LiftRow>;

Result<std::vector<hal::GyroSample>> read_gyro_csv(const std::string& path,
                                                   const RowLimits& limits) {
  return read_all<hal::GyroSample>(path, limits);
}

Result<std::vector<hal::EncoderSample>> read_encoders_csv(const std::string& path,
                                                          const RowLimits& limits) {
  return read_all<hal::EncoderSample>(path, limits);
}

Result<std::vector<CameraIndexRow>> read_camera_csv(const std::string& path,
                                                    const RowLimits& limits) {
  return read_all<CameraIndexRow>(path, limits);
}

Result<std::vector<FeatureRow>> read_features_csv(const std::string& path,
                                                  const RowLimits& limits) {
  return read_all<FeatureRow>(path, limits);
}

Result<std::vector<GroundTruthPose>> read_groundtruth_csv(const std::string& path,
                                                          const RowLimits& limits) {
  return read_all<GroundTruthPose>(path, limits);
}

Result<std::vector<LiftRow>> read_lift_csv(const std::string& path, const RowLimits& limits) {
  return read_all<LiftRow>(path, limits);
}

}  // namespace cleanslam::readers
