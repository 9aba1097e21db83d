#include "cleanslam/sim_hal/dataset_writer.hpp"

#include <filesystem>

#include "cleanslam/sim_hal/gray_image_writer.hpp"

namespace cleanslam::sim_hal {
namespace fs = std::filesystem;

readers::Status DatasetWriter::open_stream(std::ofstream& out, const std::string& relative,
                                           const char* header) {
  const fs::path path = fs::path(folder_) / relative;
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  out.open(path, std::ios::binary | std::ios::trunc);
  if (!out) {
    return readers::Status::failure(path.string() + ": cannot create file");
  }
  out << header << '\n';
  return readers::Status();
}

readers::Status DatasetWriter::open(const std::string& folder, const hal::Calibration& calibration,
                                    ImageFormat image_format) {
  folder_ = folder;
  image_format_ = image_format;
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec || !fs::is_directory(folder)) {
    return readers::Status::failure(folder + ": cannot create folder: " + ec.message());
  }
  {
    std::ofstream yaml(fs::path(folder) / "sensors.yaml", std::ios::binary | std::ios::trunc);
    yaml << readers::sensors_yaml_text(calibration);
    if (!yaml) {
      return readers::Status::failure(folder + "/sensors.yaml: cannot write");
    }
  }
  readers::Status s = open_stream(gyro_, "gyro.csv", "#t_ns,wz_rad_s");
  if (s) {
    s = open_stream(encoders_, "encoders.csv", "#t_ns,left_ticks,right_ticks");
  }
  return s;
}

void DatasetWriter::add_gyro(const hal::GyroSample& g) {
  gyro_ << g.t_ns << ',' << readers::format_double(g.wz_rad_s) << '\n';
}

void DatasetWriter::add_encoder(const hal::EncoderSample& e) {
  encoders_ << e.t_ns << ',' << e.left_ticks << ',' << e.right_ticks << '\n';
}

readers::Status DatasetWriter::add_image(hal::TimeNs t_ns, const hal::GrayImageView& image) {
  if (!camera_.is_open()) {
    readers::Status s = open_stream(camera_, "cam0/data.csv", "#t_ns,filename");
    if (!s) {
      return s;
    }
    std::error_code ec;
    fs::create_directories(fs::path(folder_) / "cam0" / "data", ec);
    if (ec) {
      return readers::Status::failure(folder_ +
                                      "/cam0/data: cannot create folder: " + ec.message());
    }
  }
  const bool png = image_format_ == ImageFormat::kPng;
  const std::string name = std::to_string(t_ns) + (png ? ".png" : ".pgm");
  const std::string path = (fs::path(folder_) / "cam0" / "data" / name).string();
  readers::Status s = png ? write_png(path, image) : write_pgm(path, image);
  if (!s) {
    return s;
  }
  camera_ << t_ns << ',' << name << '\n';
  return readers::Status();
}

void DatasetWriter::add_features(hal::TimeNs t_ns, const hal::FeatureObservation* features,
                                 int count) {
  if (!features_.is_open()) {
    if (!open_stream(features_, "features.csv", "#t_ns,track_id,u_px,v_px")) {
      return;
    }
  }
  for (int i = 0; i < count; ++i) {
    const hal::FeatureObservation& f = features[i];
    features_ << t_ns << ',' << f.track_id << ',' << readers::format_double(f.u_px) << ','
              << readers::format_double(f.v_px) << '\n';
  }
}

void DatasetWriter::add_groundtruth(const readers::GroundTruthPose& p) {
  if (!groundtruth_.is_open()) {
    if (!open_stream(groundtruth_, "groundtruth.csv", "#t_ns,x_m,y_m,z_m,qw,qx,qy,qz")) {
      return;
    }
  }
  groundtruth_ << p.t_ns;
  for (double v : p.position_m) {
    groundtruth_ << ',' << readers::format_double(v);
  }
  for (double v : p.orientation_wxyz) {
    groundtruth_ << ',' << readers::format_double(v);
  }
  groundtruth_ << '\n';
}

void DatasetWriter::add_lift(const readers::LiftRow& l) {
  if (!lift_.is_open()) {
    if (!open_stream(lift_, "lift.csv", "#t_ns,lifted")) {
      return;
    }
  }
  lift_ << l.t_ns << ',' << (l.lifted ? 1 : 0) << '\n';
}

readers::Status DatasetWriter::close() {
  std::string failed;
  const std::pair<std::ofstream*, const char*> files[] = {
      {&gyro_, "gyro.csv"},         {&encoders_, "encoders.csv"},       {&camera_, "cam0/data.csv"},
      {&features_, "features.csv"}, {&groundtruth_, "groundtruth.csv"}, {&lift_, "lift.csv"}};
  for (const auto& [stream, name] : files) {
    if (!stream->is_open()) {
      continue;
    }
    stream->close();
    if (!*stream && failed.empty()) {
      failed = folder_ + "/" + name + ": write error";
    }
  }
  if (!failed.empty()) {
    return readers::Status::failure(failed);
  }
  return readers::Status();
}

}  // namespace cleanslam::sim_hal
