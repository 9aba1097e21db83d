#pragma once

#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/firmware/rotating_file.hpp"
#include "cleanslam/hal/interfaces.hpp"

namespace cleanslam::firmware {

// TUM trajectory: "t x y z qx qy qz qw" per line, t in seconds. Optionally relative to the first
// pose written, and with a covariance side file FILE.cov: "t" and the 36 values of the 6x6
// covariance over (x, y, z, roll, pitch, yaw), row-major (position block rotated into the frame
// of the first pose when relative). Both files rotate together (FILE.1 and FILE.1.cov hold the same
// poses) when either reaches its Rotation's size.
class TumWriter final : public hal::PoseSink {
 public:
  TumWriter() = default;
  ~TumWriter() override = default;
  TumWriter(const TumWriter&) = delete;
  TumWriter& operator=(const TumWriter&) = delete;

  bool open(const std::string& path, bool relative_to_first, bool with_covariance,
            std::string& error, Rotation rotation = {});
  void publish(const hal::PoseEstimate& pose) override;
  void flush() override;
  // Flushes and closes both files; false when a write failed (errors() says which and why).
  bool close();
  // One message per file whose writing failed.
  [[nodiscard]] std::vector<std::string> errors() const;
  [[nodiscard]] const RotatingFile& file() const { return file_; }

 private:
  RotatingFile file_;
  RotatingFile cov_;
  bool relative_ = false;
  bool have_first_ = false;
  std::array<double, 3> p0_{};
  std::array<double, 4> q0_{1.0, 0.0, 0.0, 0.0};  // w x y z
};

// Diagnostics records as a CSV file with a header line (each rotated file starts with it);
// nothing is written before open().
class CsvSink : public UpdateSink {
 public:
  CsvSink() = default;
  ~CsvSink() override = default;
  CsvSink(const CsvSink&) = delete;
  CsvSink& operator=(const CsvSink&) = delete;

  void flush() override;
  // Flushes and closes; false when a write failed (file().error() says why).
  bool close() { return file_.close(); }
  [[nodiscard]] const RotatingFile& file() const { return file_; }

 protected:
  bool open_with_header(const std::string& path, const char* header, std::string& error,
                        Rotation rotation);
  // Starts a row: rotates first when the file is full.
  RotatingFile& row();

 private:
  RotatingFile file_;
  const char* header_ = "";
};

// The per-update diagnostics records as CSV.
class DiagnosticsCsv final : public CsvSink {
 public:
  bool open(const std::string& path, std::string& error, Rotation rotation = {});
  void update(const hal::log::UpdateRecord& r) override;
};

const char* to_string(hal::log::UpdateStatus s);

}  // namespace cleanslam::firmware
