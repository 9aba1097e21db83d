#pragma once

#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/hal/interfaces.hpp"

namespace cleanslam::firmware {

// TUM trajectory: "t x y z qx qy qz qw" per line, t in seconds. Optionally relative to the first
// pose written, and with a covariance side file FILE.cov: "t" and the 36 values of the 6x6
// covariance over (x, y, z, roll, pitch, yaw), row-major (position block rotated into the frame
// of the first pose when relative).
class TumWriter final : public hal::PoseSink {
 public:
  TumWriter() = default;
  ~TumWriter() override;
  TumWriter(const TumWriter&) = delete;
  TumWriter& operator=(const TumWriter&) = delete;

  bool open(const std::string& path, bool relative_to_first, bool with_covariance,
            std::string& error);
  void publish(const hal::PoseEstimate& pose) override;
  void flush() override;
  void close();

 private:
  std::FILE* file_ = nullptr;
  std::FILE* cov_ = nullptr;
  std::vector<char> buffer_;
  std::vector<char> cov_buffer_;
  bool relative_ = false;
  bool have_first_ = false;
  std::array<double, 3> p0_{};
  std::array<double, 4> q0_{1.0, 0.0, 0.0, 0.0};  // w x y z
};

// Diagnostics records as a CSV file with a header line; nothing is written before open().
class CsvSink : public UpdateSink {
 public:
  CsvSink() = default;
  ~CsvSink() override;
  CsvSink(const CsvSink&) = delete;
  CsvSink& operator=(const CsvSink&) = delete;

  void flush() override;

 protected:
  bool open_with_header(const std::string& path, const char* header, std::string& error);
  std::FILE* file_ = nullptr;

 private:
  std::vector<char> buffer_;
};

// The per-update diagnostics records as CSV.
class DiagnosticsCsv final : public CsvSink {
 public:
  bool open(const std::string& path, std::string& error);
  void update(const hal::log::UpdateRecord& r) override;
};

const char* to_string(hal::log::UpdateStatus s);

}  // namespace cleanslam::firmware
