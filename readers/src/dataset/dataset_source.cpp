#include "cleanslam/readers/dataset_source.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "dataset_scan.hpp"
#include "row_reader.hpp"

namespace cleanslam::readers {
namespace {
constexpr hal::TimeNs kNever = std::numeric_limits<hal::TimeNs>::max();
constexpr auto kMaxFeatures = static_cast<std::size_t>(hal::kMaxFeaturesPerFrame);
}  // namespace

// The files of the folder, each with its next row read ahead.
struct DatasetSource::Streams {
  template <typename Row>
  struct Stream {
    RowReader<Row> reader;
    Row next;
    bool has_next = false;
  };

  // The rows of the next frame: its camera row and its features (the first kMaxFeatures).
  struct FrameRows {
    hal::TimeNs t_ns = 0;
    bool has_camera = false;
    std::size_t feature_rows = 0;  // all of them, also those past kMaxFeatures
  };

  Status open(const DatasetSummary& summary, hal::TimeNs max_span_ns) {
    // The files were read at open(): their warnings and refused rows were told then.
    const RowLimits limits{max_span_ns, &told_before, nullptr};
    const std::string& folder = summary.folder;
    Status s = start(gyro, dataset_file(folder, DatasetFile::kGyro), limits);
    if (s) {
      s = start(encoders, dataset_file(folder, DatasetFile::kEncoders), limits);
    }
    if (s && summary.has_camera) {
      s = start(camera, dataset_file(folder, DatasetFile::kCamera), limits);
    }
    if (s && summary.has_features) {
      s = start(features, dataset_file(folder, DatasetFile::kFeatures), limits);
    }
    const std::string lift_csv = dataset_file(folder, DatasetFile::kLift);
    std::error_code ec;
    if (s && std::filesystem::exists(lift_csv, ec)) {
      s = start(lift, lift_csv, limits);
    }
    if (!s) {
      error = s.error();
      end_all();
    }
    return s;
  }

  template <typename Row>
  Status start(Stream<Row>& stream, const std::string& path, const RowLimits& limits) {
    Status s = stream.reader.open(path, limits);
    if (s) {
      advance(stream);
    }
    return s;
  }

  template <typename Row>
  void advance(Stream<Row>& stream) {
    stream.has_next = stream.reader.next(stream.next);
    told_before.clear();
    if (!stream.has_next && !stream.reader.error().empty() && error.empty()) {
      error = stream.reader.error();
      end_all();
    }
  }

  void end_all() {
    gyro.has_next = false;
    encoders.has_next = false;
    camera.has_next = false;
    features.has_next = false;
    lift.has_next = false;
  }

  [[nodiscard]] bool has_frame() const { return camera.has_next || features.has_next; }
  [[nodiscard]] hal::TimeNs next_frame_time() const {
    return std::min(camera.has_next ? camera.next.t_ns : kNever,
                    features.has_next ? features.next.t_ns : kNever);
  }

  FrameRows take_frame(CameraIndexRow& camera_row,
                       std::vector<hal::FeatureObservation>& observations) {
    FrameRows f;
    f.t_ns = next_frame_time();
    observations.clear();
    if (camera.has_next && camera.next.t_ns == f.t_ns) {
      std::swap(camera_row, camera.next);
      f.has_camera = true;
      advance(camera);
    }
    while (features.has_next && features.next.t_ns == f.t_ns) {
      if (observations.size() < kMaxFeatures) {
        observations.push_back(features.next.observation);
      }
      ++f.feature_rows;
      advance(features);
    }
    return f;
  }

  Stream<hal::GyroSample> gyro;
  Stream<hal::EncoderSample> encoders;
  Stream<CameraIndexRow> camera;
  Stream<FeatureRow> features;
  Stream<LiftRow> lift;
  std::vector<std::string> told_before;
  std::string error;
};

DatasetSource::DatasetSource() = default;
DatasetSource::DatasetSource(DatasetSource&&) noexcept = default;
DatasetSource& DatasetSource::operator=(DatasetSource&&) noexcept = default;
DatasetSource::~DatasetSource() = default;

Result<DatasetSource> DatasetSource::open(const std::string& folder, const Options& options) {
  using R = Result<DatasetSource>;
  DatasetSource src;
  DatasetSummary& summary = src.summary_;
  const auto span = [&summary](const auto& row) {
    if (summary.first_ns < 0 || row.t_ns < summary.first_ns) {
      summary.first_ns = row.t_ns;
    }
    summary.last_ns = std::max(summary.last_ns, row.t_ns);
  };
  RowVisitors visit;
  visit.gyro = span;
  visit.encoders = span;
  Dataset d;
  Status s = scan_dataset(folder, options.load, visit, d);
  if (!s) {
    return R::failure(s.error());
  }
  summary.folder = d.folder;
  summary.calibration = d.calibration;
  summary.has_camera = d.has_camera;
  summary.has_features = d.has_features;
  summary.warnings = std::move(d.warnings);
  summary.rows_refused = d.rows_refused;
  if (options.apply_time_offset) {
    src.frame_offset_ns_ =
        static_cast<hal::TimeNs>(std::llround(summary.calibration.camera.time_offset_s * 1e9));
  }
  src.frame_features_.reserve(kMaxFeatures);

  // The frames as the run will see them: counted, and those with too many features told.
  Streams frames;
  s = frames.open(summary, options.load.max_span_ns);
  while (s && frames.has_frame()) {
    const Streams::FrameRows f = frames.take_frame(src.camera_row_, src.frame_features_);
    if (f.feature_rows > kMaxFeatures) {
      summary.warnings.push_back(folder + "/features.csv: frame at t_ns " + std::to_string(f.t_ns) +
                                 " has " + std::to_string(f.feature_rows) +
                                 " features, only the first " + std::to_string(kMaxFeatures) +
                                 " are used");
    }
    ++summary.frames;
  }
  if (!frames.error.empty()) {
    return R::failure(frames.error);
  }

  src.streams_ = std::make_unique<Streams>();
  s = src.streams_->open(summary, options.load.max_span_ns);
  if (!s) {
    return R::failure(s.error());
  }
  return src;
}

const std::string& DatasetSource::stream_error() const {
  return streams_->error;
}

hal::TimeNs DatasetSource::next_event_time() const {
  if (exhausted()) {
    return -1;
  }
  const Streams& s = *streams_;
  hal::TimeNs t = kNever;
  if (s.gyro.has_next) {
    t = std::min(t, s.gyro.next.t_ns);
  }
  if (s.encoders.has_next) {
    t = std::min(t, s.encoders.next.t_ns);
  }
  if (s.lift.has_next) {
    t = std::min(t, s.lift.next.t_ns);
  }
  if (s.has_frame()) {
    t = std::min(t, hal::add_saturated(s.next_frame_time(), frame_offset_ns_));
  }
  return t;
}

bool DatasetSource::exhausted() const {
  const Streams& s = *streams_;
  return !s.gyro.has_next && !s.encoders.has_next && !s.lift.has_next && !s.has_frame();
}

bool DatasetSource::read(hal::SensorEvent& out) {
  if (exhausted()) {
    return false;
  }
  Streams& s = *streams_;
  const hal::TimeNs t = next_event_time();
  out = hal::SensorEvent{};
  if (s.gyro.has_next && s.gyro.next.t_ns == t) {
    out.kind = hal::SensorEvent::Kind::kGyro;
    out.gyro = s.gyro.next;
    s.advance(s.gyro);
    return true;
  }
  if (s.encoders.has_next && s.encoders.next.t_ns == t) {
    out.kind = hal::SensorEvent::Kind::kEncoder;
    out.encoder = s.encoders.next;
    s.advance(s.encoders);
    return true;
  }
  if (s.lift.has_next && s.lift.next.t_ns == t) {
    out.kind = hal::SensorEvent::Kind::kLift;
    out.lifted = s.lift.next.lifted;
    s.advance(s.lift);
    return true;
  }
  const Streams::FrameRows f = s.take_frame(camera_row_, frame_features_);
  out.kind = hal::SensorEvent::Kind::kFrame;
  out.frame.t_ns = t;
  out.frame.seq = static_cast<std::uint32_t>(next_frame_);
  if (f.has_camera) {
    const std::string path = image_path(summary_.folder, camera_row_);
    Status st = read_dataset_image(summary_.folder, path, image_);
    if (st && (image_.width != summary_.calibration.camera.width ||
               image_.height != summary_.calibration.camera.height)) {
      st = Status::failure(path + ": wrong image size");
    }
    if (st) {
      out.frame.image = image_.view();
    } else {
      ++image_errors_;
      last_error_ = st.error();
      if (image_errors_ <= kMaxImageErrorsTold) {
        image_error_messages_.push_back(
            summary_.folder + "/cam0/data.csv:" + std::to_string(camera_row_.line) +
            ": filename: " + st.error() + ": the frame went on without its image");
      }
    }
  }
  if (!frame_features_.empty()) {
    out.frame.features = frame_features_.data();
    out.frame.feature_count = static_cast<int>(frame_features_.size());
  }
  ++next_frame_;
  return true;
}

}  // namespace cleanslam::readers
