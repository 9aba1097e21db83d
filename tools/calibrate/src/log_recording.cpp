#include "cleanslam/calibrate/log_recording.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>

#include "cleanslam/calibrate/text.hpp"
#include "cleanslam/readers/log_source.hpp"

namespace cleanslam::calibrate {
namespace {

using readers::LogDefect;
using readers::LogReader;
using readers::LogSource;

// The files a later file of a rotated recording continues, oldest first, ending with it: the
// recorder names them LOG.k ... LOG.1, LOG (newest), so that LOG.j continues LOG.(j+1).
std::string rotated_files(const std::string& path, std::uint32_t file_index) {
  std::string base = path;
  unsigned long suffix = 0;
  const std::size_t dot = path.find_last_of('.');
  if (dot != std::string::npos && dot + 1 < path.size() && path.size() - dot <= 6 &&
      path.find_first_not_of("0123456789", dot + 1) == std::string::npos) {
    base = path.substr(0, dot);
    suffix = std::stoul(path.substr(dot + 1));
  }
  std::string files;
  for (unsigned long j = suffix + file_index; j > suffix; --j) {
    files += base + "." + std::to_string(j) + " ";
  }
  return files + path;
}

// Opens the log (nullptr after setting `error`, which names the file) and says what is wrong
// with it: the records refused as damaged, a truncation, a later file of a rotated recording.
std::unique_ptr<LogReader> open_log(const std::string& path, std::vector<std::string>& warnings,
                                    std::string& error) {
  auto log = std::make_unique<LogReader>();
  if (!log->open(path)) {
    error = log->error();
    return nullptr;
  }
  for (int d = 0; d < static_cast<int>(LogDefect::kCount); ++d) {
    const auto defect = static_cast<LogDefect>(d);
    if (log->defects(defect) > 0) {
      warnings.push_back(path + ": " + std::to_string(log->defects(defect)) + " " +
                         readers::to_string(defect) + " record(s) refused");
    }
  }
  if (log->defects(LogDefect::kTruncated) > 0) {
    warnings.push_back(path + " is truncated at byte " + std::to_string(log->truncated_at()) +
                       ": read up to its last whole record");
  }
  if (!log->join_error().empty()) {
    warnings.push_back(path + ": " + log->join_error());
  }
  if (log->file_index() > 0) {
    warnings.push_back(path + " is file " + std::to_string(log->file_index()) +
                       " of a rotated recording (its header's file index; 0 is the file the run "
                       "began in): only the recording's part in it is read; to calibrate from "
                       "the whole recording, join its files oldest first (those recorder.max_files "
                       "kept): cat " +
                       rotated_files(path, log->file_index()) + " > joined.log");
  }
  return log;
}

// What the source refused while reading: counts, then its first messages.
void source_warnings(const std::string& path, const LogSource& source,
                     std::vector<std::string>& warnings) {
  const auto count = [&](std::uint64_t n, const char* what) {
    if (n > 0) {
      warnings.push_back(path + ": " + std::to_string(n) + " record(s) refused: " + what);
    }
  };
  count(source.payload_defects(), "the payload does not decode");
  count(source.stamps_refused(), "stamped before the log's start or beyond its span");
  count(source.out_of_place(), "stamped after the next sample of the same sensor");
  for (const std::string& m : source.messages()) {
    warnings.push_back(m);
  }
}

GrayImage copied(const hal::GrayImageView& v, std::string name) {
  GrayImage g{std::move(name), v.width, v.height, {}};
  g.pixels.reserve(static_cast<std::size_t>(v.width) * static_cast<std::size_t>(v.height));
  for (int y = 0; y < v.height; ++y) {
    g.pixels.insert(g.pixels.end(), v.row(y), v.row(y) + v.width);
  }
  return g;
}

}  // namespace

readers::Result<readers::Dataset> read_log_samples(const std::string& path,
                                                   std::vector<std::string>& warnings) {
  using SamplesResult = readers::Result<readers::Dataset>;
  std::string error;
  const std::unique_ptr<LogReader> log = open_log(path, warnings, error);
  if (!log) {
    return SamplesResult::failure(error);
  }
  readers::Dataset d;
  d.folder = path;
  LogSource source(*log, LogSource::Pacing::kEventTime);
  hal::SensorEvent ev;
  while (!source.exhausted()) {
    if (!source.read(ev)) {
      break;
    }
    if (ev.kind == hal::SensorEvent::Kind::kGyro) {
      d.gyro.push_back(ev.gyro);
    }
    if (ev.kind == hal::SensorEvent::Kind::kEncoder) {
      d.encoders.push_back(ev.encoder);
    }
  }
  source_warnings(path, source, warnings);
  const auto by_time = [](const auto& a, const auto& b) { return a.t_ns < b.t_ns; };
  std::stable_sort(d.gyro.begin(), d.gyro.end(), by_time);
  std::stable_sort(d.encoders.begin(), d.encoders.end(), by_time);
  if (d.gyro.empty() && d.encoders.empty()) {
    return SamplesResult::failure(path + ": no gyro or encoder record among its " +
                                  std::to_string(log->records().size()) + " valid records (" +
                                  std::to_string(log->total_defects()) +
                                  " refused as damaged): nothing to calibrate from");
  }
  return d;
}

readers::Result<LogFrames> read_log_frames(const std::string& path, int every, int max_views,
                                           std::vector<std::string>& warnings) {
  using FramesResult = readers::Result<LogFrames>;
  std::string error;
  const std::unique_ptr<LogReader> log = open_log(path, warnings, error);
  if (!log) {
    return FramesResult::failure(error);
  }
  LogFrames out;
  // Two passes: the frames are counted first, so that only the kept ones are copied.
  for (int pass = 0; pass < 2; ++pass) {
    LogSource source(*log, LogSource::Pacing::kEventTime);
    hal::SensorEvent ev;
    int with_image = 0;
    while (!source.exhausted() && source.read(ev)) {
      if (ev.kind != hal::SensorEvent::Kind::kFrame) {
        continue;
      }
      if (pass == 0) {
        ++out.frame_records;
      }
      if (!ev.frame.has_image()) {
        continue;
      }
      if (pass == 1 && with_image % out.every == 0) {
        out.views.images.push_back(
            copied(ev.frame.image, path + ": frame " + std::to_string(ev.frame.seq) + " at " +
                                       fixed(hal::to_seconds(ev.frame.t_ns), 3) + " s"));
      }
      ++with_image;
    }
    if (pass == 1) {
      source_warnings(path, source, warnings);
      break;
    }
    out.frames_with_image = with_image;
    if (out.frame_records == 0) {
      return FramesResult::failure(path +
                                   ": no frame record: record the camera's frames with their "
                                   "images (recorder.frame_every 1)");
    }
    if (with_image == 0) {
      return FramesResult::failure(
          path + ": none of its " + std::to_string(out.frame_records) +
          " frames carries an image (features only): record from the camera, with images, and "
          "recorder.frame_every 1");
    }
    out.every =
        every > 0 ? every : std::max(1, (with_image + max_views - 1) / std::max(1, max_views));
  }
  return out;
}

}  // namespace cleanslam::calibrate
