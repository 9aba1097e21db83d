#include <cmath>
#include <filesystem>
#include <limits>

#include "cleanslam/readers/csv.hpp"
#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/gray_image.hpp"

namespace cleanslam::readers {
namespace fs = std::filesystem;
namespace {

// Time stamp in column 0, checked against the previous row's.
std::string read_time(const CsvRow& row, hal::TimeNs previous, bool first, bool strictly,
                      hal::TimeNs& out) {
  auto t = row.integer(0);
  if (!t.ok()) return t.error();
  if (*t < 0) return row.fail(0, "negative time stamp " + std::to_string(*t));
  if (!first && (*t < previous || (strictly && *t == previous))) {
    return row.fail(0, "time stamp " + std::to_string(*t) + " is not after the previous row's " +
                           std::to_string(previous) + " (rows must be sorted by time)");
  }
  out = *t;
  return {};
}

// Tick counts are 32-bit counters; values written as unsigned (up to 2^32 - 1) wrap.
std::string read_ticks(const CsvRow& row, std::size_t i, std::int32_t& out) {
  auto v = row.integer(i);
  if (!v.ok()) return v.error();
  if (*v < std::numeric_limits<std::int32_t>::min() ||
      *v > static_cast<std::int64_t>(std::numeric_limits<std::uint32_t>::max())) {
    return row.fail(i, std::to_string(*v) + " does not fit a 32-bit counter");
  }
  out = static_cast<std::int32_t>(static_cast<std::uint32_t>(*v));
  return {};
}

}  // namespace

Result<std::vector<hal::GyroSample>> read_gyro_csv(const std::string& path) {
  using R = Result<std::vector<hal::GyroSample>>;
  std::vector<hal::GyroSample> out;
  std::vector<std::string> columns;
  Status s = read_csv(
      path, CsvSpec{{"t_ns", "wz_rad_s"}, {"wx_rad_s", "wy_rad_s"}},
      [&](const CsvRow& row) -> std::string {
        hal::GyroSample g;
        std::string e =
            read_time(row, out.empty() ? 0 : out.back().t_ns, out.empty(), true, g.t_ns);
        if (!e.empty()) return e;
        auto wz = row.number(1);
        if (!wz.ok()) return wz.error();
        g.wz_rad_s = *wz;
        if (row.size() == 4) {
          auto wx = row.number(2);
          if (!wx.ok()) return wx.error();
          auto wy = row.number(3);
          if (!wy.ok()) return wy.error();
          g.wx_rad_s = *wx;
          g.wy_rad_s = *wy;
          g.has_xy = true;
        }
        g.seq = static_cast<std::uint32_t>(out.size());
        out.push_back(g);
        return {};
      },
      &columns);
  if (!s) return R::failure(s.error());
  return out;
}

Result<std::vector<hal::EncoderSample>> read_encoders_csv(const std::string& path) {
  using R = Result<std::vector<hal::EncoderSample>>;
  std::vector<hal::EncoderSample> out;
  Status s = read_csv(path, CsvSpec{{"t_ns", "left_ticks", "right_ticks"}, {}},
                      [&](const CsvRow& row) -> std::string {
                        hal::EncoderSample e;
                        std::string err = read_time(row, out.empty() ? 0 : out.back().t_ns,
                                                    out.empty(), true, e.t_ns);
                        if (err.empty()) err = read_ticks(row, 1, e.left_ticks);
                        if (err.empty()) err = read_ticks(row, 2, e.right_ticks);
                        if (!err.empty()) return err;
                        e.seq = static_cast<std::uint32_t>(out.size());
                        out.push_back(e);
                        return {};
                      });
  if (!s) return R::failure(s.error());
  return out;
}

Result<std::vector<CameraIndexRow>> read_camera_csv(const std::string& path) {
  using R = Result<std::vector<CameraIndexRow>>;
  std::vector<CameraIndexRow> out;
  Status s =
      read_csv(path, CsvSpec{{"t_ns", "filename"}, {}}, [&](const CsvRow& row) -> std::string {
        CameraIndexRow c;
        std::string err =
            read_time(row, out.empty() ? 0 : out.back().t_ns, out.empty(), true, c.t_ns);
        if (!err.empty()) return err;
        const std::string_view name = row.text(1);
        if (name.empty()) return row.fail(1, "empty file name");
        const bool parent = name == ".." || name.starts_with("../") || name.ends_with("/..") ||
                            name.find("/../") != std::string_view::npos;
        if (name.front() == '/' || parent) {
          return row.fail(
              1, "file name must be relative to cam0/data/, got \"" + std::string(name) + "\"");
        }
        c.filename = std::string(name);
        c.line = row.line();
        out.push_back(std::move(c));
        return {};
      });
  if (!s) return R::failure(s.error());
  return out;
}

Result<std::vector<FeatureRow>> read_features_csv(const std::string& path) {
  using R = Result<std::vector<FeatureRow>>;
  std::vector<FeatureRow> out;
  Status s = read_csv(path, CsvSpec{{"t_ns", "track_id", "u_px", "v_px"}, {}},
                      [&](const CsvRow& row) -> std::string {
                        FeatureRow f;
                        std::string err = read_time(row, out.empty() ? 0 : out.back().t_ns,
                                                    out.empty(), false, f.t_ns);
                        if (!err.empty()) return err;
                        auto id = row.integer(1);
                        if (!id.ok()) return id.error();
                        if (*id < 0) return row.fail(1, "track id must be non-negative");
                        auto u = row.number(2);
                        if (!u.ok()) return u.error();
                        auto v = row.number(3);
                        if (!v.ok()) return v.error();
                        f.observation = hal::FeatureObservation{*id, *u, *v};
                        out.push_back(f);
                        return {};
                      });
  if (!s) return R::failure(s.error());
  return out;
}

Result<std::vector<GroundTruthPose>> read_groundtruth_csv(const std::string& path) {
  using R = Result<std::vector<GroundTruthPose>>;
  std::vector<GroundTruthPose> out;
  Status s =
      read_csv(path, CsvSpec{{"t_ns", "x_m", "y_m", "z_m", "qw", "qx", "qy", "qz"}, {}},
               [&](const CsvRow& row) -> std::string {
                 GroundTruthPose p;
                 std::string err =
                     read_time(row, out.empty() ? 0 : out.back().t_ns, out.empty(), true, p.t_ns);
                 if (!err.empty()) return err;
                 double v[7];
                 for (std::size_t i = 0; i < 7; ++i) {
                   auto x = row.number(i + 1);
                   if (!x.ok()) return x.error();
                   v[i] = *x;
                 }
                 const double n = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
                 if (std::abs(n - 1.0) > 1e-3) {
                   return row.fail(4, "quaternion norm " + format_double(n) + " is not 1");
                 }
                 p.position_m = {v[0], v[1], v[2]};
                 p.orientation_wxyz = {v[3] / n, v[4] / n, v[5] / n, v[6] / n};
                 out.push_back(p);
                 return {};
               });
  if (!s) return R::failure(s.error());
  return out;
}

Result<std::vector<LiftRow>> read_lift_csv(const std::string& path) {
  using R = Result<std::vector<LiftRow>>;
  std::vector<LiftRow> out;
  Status s = read_csv(path, CsvSpec{{"t_ns", "lifted"}, {}}, [&](const CsvRow& row) -> std::string {
    LiftRow l;
    std::string err = read_time(row, out.empty() ? 0 : out.back().t_ns, out.empty(), true, l.t_ns);
    if (!err.empty()) return err;
    auto v = row.integer(1);
    if (!v.ok()) return v.error();
    if (*v != 0 && *v != 1) return row.fail(1, "expected 0 or 1, got " + std::to_string(*v));
    l.lifted = *v == 1;
    out.push_back(l);
    return {};
  });
  if (!s) return R::failure(s.error());
  return out;
}

std::string Dataset::image_path(const CameraIndexRow& row) const {
  return (fs::path(folder) / "cam0" / "data" / row.filename).string();
}

Result<Dataset> load_dataset(const std::string& folder, const LoadOptions& options) {
  using R = Result<Dataset>;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return R::failure(folder + ": not a dataset folder");
  Dataset d;
  d.folder = folder;
  const fs::path root(folder);
  auto cal = read_sensors_yaml((root / "sensors.yaml").string(), &d.warnings);
  if (!cal.ok()) return R::failure(cal.error());
  d.calibration = *cal;
  auto gyro = read_gyro_csv((root / "gyro.csv").string());
  if (!gyro.ok()) return R::failure(gyro.error());
  d.gyro = std::move(gyro).value();
  auto enc = read_encoders_csv((root / "encoders.csv").string());
  if (!enc.ok()) return R::failure(enc.error());
  d.encoders = std::move(enc).value();

  const fs::path cam_csv = root / "cam0" / "data.csv";
  const fs::path features_csv = root / "features.csv";
  d.has_camera = fs::exists(cam_csv, ec);
  d.has_features = fs::exists(features_csv, ec);
  if (!d.has_camera && !d.has_features) {
    return R::failure(folder + ": neither cam0/data.csv nor features.csv found (one is required)");
  }
  if (d.has_camera) {
    auto cam = read_camera_csv(cam_csv.string());
    if (!cam.ok()) return R::failure(cam.error());
    d.camera = std::move(cam).value();
    if (options.check_images) {
      for (std::size_t i = 0; i < d.camera.size(); ++i) {
        const std::string where =
            cam_csv.string() + ":" + std::to_string(d.camera[i].line) + ": filename: ";
        const std::string path = d.image_path(d.camera[i]);
        if (!fs::is_regular_file(path, ec)) return R::failure(where + path + ": image not found");
        auto size = read_gray_image_size(path);
        if (!size.ok()) return R::failure(where + size.error());
        if (size->width != d.calibration.camera.width ||
            size->height != d.calibration.camera.height) {
          return R::failure(where + path + ": image is " + std::to_string(size->width) + "x" +
                            std::to_string(size->height) + ", sensors.yaml says " +
                            std::to_string(d.calibration.camera.width) + "x" +
                            std::to_string(d.calibration.camera.height));
        }
      }
    }
  }
  if (d.has_features) {
    auto f = read_features_csv(features_csv.string());
    if (!f.ok()) return R::failure(f.error());
    d.features = std::move(f).value();
  }
  const fs::path lift = root / "lift.csv";
  if (fs::exists(lift, ec)) {
    auto l = read_lift_csv(lift.string());
    if (!l.ok()) return R::failure(l.error());
    d.lift = std::move(l).value();
  }
  const fs::path gt = root / "groundtruth.csv";
  d.has_groundtruth = fs::exists(gt, ec);
  if (d.has_groundtruth) {
    auto g = read_groundtruth_csv(gt.string());
    if (!g.ok()) return R::failure(g.error());
    d.groundtruth = std::move(g).value();
  }
  return d;
}

}  // namespace cleanslam::readers
