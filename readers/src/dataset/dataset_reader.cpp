#include <algorithm>
#include <filesystem>

#include "cleanslam/readers/dataset.hpp"
#include "cleanslam/readers/gray_image.hpp"
#include "dataset_scan.hpp"
#include "row_reader.hpp"

namespace cleanslam::readers {
namespace fs = std::filesystem;
namespace {

template <typename Row>
Status visit_rows(const std::string& path, const RowLimits& limits,
                  const std::function<void(const Row&)>& visit) {
  RowReader<Row> reader;
  Status s = reader.open(path, limits);
  if (!s) {
    return s;
  }
  Row row;
  while (reader.next(row)) {
    if (visit) {
      visit(row);
    }
  }
  if (!reader.error().empty()) {
    return Status::failure(reader.error());
  }
  return Status();
}

// Every image of cam0/data.csv exists and has the calibrated size (headers only). The file was
// read before: its warnings are not told again.
Status check_images(const std::string& cam_csv, const Dataset& d, const RowLimits& limits) {
  std::vector<std::string> told_before;
  const RowLimits quiet{limits.max_span_ns, &told_before, nullptr};
  RowReader<CameraIndexRow> reader;
  Status s = reader.open(cam_csv, quiet);
  if (!s) {
    return s;
  }
  CameraIndexRow row;
  std::error_code ec;
  while (reader.next(row)) {
    const std::string where = cam_csv + ":" + std::to_string(row.line) + ": filename: ";
    const std::string path = d.image_path(row);
    if (!fs::exists(path, ec)) {
      return Status::failure(where + path + ": image not found");
    }
    auto size = read_dataset_image_size(d.folder, path);
    if (!size.ok()) {
      return Status::failure(where + size.error());
    }
    if (size->width != d.calibration.camera.width || size->height != d.calibration.camera.height) {
      return Status::failure(where + path + ": image is " + std::to_string(size->width) + "x" +
                             std::to_string(size->height) + ", sensors.yaml says " +
                             std::to_string(d.calibration.camera.width) + "x" +
                             std::to_string(d.calibration.camera.height));
    }
    told_before.clear();
  }
  if (!reader.error().empty()) {
    return Status::failure(reader.error());
  }
  return Status();
}

}  // namespace

std::string dataset_file(const std::string& folder, DatasetFile file) {
  const fs::path root(folder);
  switch (file) {
    case DatasetFile::kGyro:
      return (root / "gyro.csv").string();
    case DatasetFile::kEncoders:
      return (root / "encoders.csv").string();
    case DatasetFile::kCamera:
      return (root / "cam0" / "data.csv").string();
    case DatasetFile::kFeatures:
      return (root / "features.csv").string();
    case DatasetFile::kLift:
      return (root / "lift.csv").string();
    case DatasetFile::kGroundTruth:
      break;
  }
  return (root / "groundtruth.csv").string();
}

std::string image_path(const std::string& folder, const CameraIndexRow& row) {
  return (fs::path(folder) / "cam0" / "data" / row.filename).string();
}

namespace {

// The image's path, through symbolic links, stays inside the dataset folder.
Status inside_dataset(const std::string& folder, const std::string& path) {
  std::error_code ec;
  const fs::path root = fs::canonical(folder, ec);
  if (ec) {
    return Status::failure(folder + ": " + ec.message());
  }
  const fs::path target = fs::weakly_canonical(path, ec);
  if (ec) {
    return Status::failure(path + ": " + ec.message());
  }
  const auto [r, t] = std::mismatch(root.begin(), root.end(), target.begin(), target.end());
  if (r != root.end()) {
    return Status::failure(path + ": leads to " + target.string() +
                           ", outside the dataset folder " + root.string() +
                           " (a symbolic link out of it): refused");
  }
  return Status();
}

}  // namespace

Status read_dataset_image(const std::string& folder, const std::string& path, GrayImage& out) {
  Status s = inside_dataset(folder, path);
  if (!s) {
    return s;
  }
  return read_gray_image(path, out);
}

Result<ImageSize> read_dataset_image_size(const std::string& folder, const std::string& path) {
  Status s = inside_dataset(folder, path);
  if (!s) {
    return Result<ImageSize>::failure(s.error());
  }
  return read_gray_image_size(path);
}

std::string Dataset::image_path(const CameraIndexRow& row) const {
  return readers::image_path(folder, row);
}

Status scan_dataset(const std::string& folder, const LoadOptions& options, const RowVisitors& visit,
                    Dataset& d) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    return Status::failure(folder + ": not a dataset folder");
  }
  d.folder = folder;
  const fs::path root(folder);
  auto cal = read_sensors_yaml((root / "sensors.yaml").string(), &d.warnings);
  if (!cal.ok()) {
    return Status::failure(cal.error());
  }
  d.calibration = *cal;
  const RowLimits limits{options.max_span_ns, &d.warnings, &d.rows_refused};
  Status s = visit_rows(dataset_file(folder, DatasetFile::kGyro), limits, visit.gyro);
  if (!s) {
    return s;
  }
  s = visit_rows(dataset_file(folder, DatasetFile::kEncoders), limits, visit.encoders);
  if (!s) {
    return s;
  }

  const std::string cam_csv = dataset_file(folder, DatasetFile::kCamera);
  const std::string features_csv = dataset_file(folder, DatasetFile::kFeatures);
  d.has_camera = fs::exists(cam_csv, ec);
  d.has_features = fs::exists(features_csv, ec);
  if (!d.has_camera && !d.has_features) {
    return Status::failure(folder +
                           ": neither cam0/data.csv nor features.csv found (one is required)");
  }
  if (d.has_camera) {
    s = visit_rows(cam_csv, limits, visit.camera);
    if (!s) {
      return s;
    }
    if (options.check_images) {
      s = check_images(cam_csv, d, limits);
      if (!s) {
        return s;
      }
    }
  }
  if (d.has_features) {
    s = visit_rows(features_csv, limits, visit.features);
    if (!s) {
      return s;
    }
  }
  const std::string lift = dataset_file(folder, DatasetFile::kLift);
  if (fs::exists(lift, ec)) {
    s = visit_rows(lift, limits, visit.lift);
    if (!s) {
      return s;
    }
  }
  const std::string gt = dataset_file(folder, DatasetFile::kGroundTruth);
  d.has_groundtruth = fs::exists(gt, ec);
  if (d.has_groundtruth) {
    s = visit_rows(gt, limits, visit.groundtruth);
    if (!s) {
      return s;
    }
  }
  return Status();
}

Result<Dataset> load_dataset(const std::string& folder, const LoadOptions& options) {
  Dataset d;
  RowVisitors keep;
  keep.gyro = [&d](const hal::GyroSample& r) { d.gyro.push_back(r); };
  keep.encoders = [&d](const hal::EncoderSample& r) { d.encoders.push_back(r); };
  keep.camera = [&d](const CameraIndexRow& r) { d.camera.push_back(r); };
  keep.features = [&d](const FeatureRow& r) { d.features.push_back(r); };
  keep.lift = [&d](const LiftRow& r) { d.lift.push_back(r); };
  keep.groundtruth = [&d](const GroundTruthPose& r) { d.groundtruth.push_back(r); };
  Status s = scan_dataset(folder, options, keep, d);
  if (!s) {
    return Result<Dataset>::failure(s.error());
  }
  return d;
}

}  // namespace cleanslam::readers
