#include "cleanslam/firmware/output_report.hpp"

#include <string>

namespace cleanslam::firmware {
namespace {

void tell_rotations(const char* program, const RotatingFile& f, const char* what, std::FILE* out) {
  if (f.rotations() == 0) {
    return;
  }
  std::fprintf(out,
               "%s: %s rotated %llu time(s) at %zu MB (sinks.max_file_mb); the earlier %s is in "
               "%s.1 ... %s.%d (sinks.max_files), anything older was deleted\n",
               program, f.path().c_str(), static_cast<unsigned long long>(f.rotations()),
               f.rotation().max_file_bytes >> 20, what, f.path().c_str(), f.path().c_str(),
               f.rotation().max_files - 1);
}

}  // namespace

bool close_and_report_outputs(const char* program, TumWriter* tum, CsvSink* diagnostics,
                              Recorder* recorder, std::FILE* out) {
  bool ok = true;
  if (recorder != nullptr && recorder->is_open()) {
    recorder->close();
  }
  if (recorder != nullptr && !recorder->write_error().empty()) {
    std::fprintf(out, "%s: error: %s\n", program, recorder->write_error().c_str());
    ok = false;
  }
  if (tum != nullptr && tum->file().is_open()) {
    tell_rotations(program, tum->file(), "trajectory (and its .cov)", out);
    if (!tum->close()) {
      for (const std::string& e : tum->errors()) {
        std::fprintf(out, "%s: error: %s: the trajectory is incomplete\n", program, e.c_str());
      }
      ok = false;
    }
  }
  if (diagnostics != nullptr && diagnostics->file().is_open()) {
    tell_rotations(program, diagnostics->file(), "diagnostics", out);
    if (!diagnostics->close()) {
      std::fprintf(out, "%s: error: %s: the diagnostics are incomplete\n", program,
                   diagnostics->file().error().c_str());
      ok = false;
    }
  }
  return ok;
}

}  // namespace cleanslam::firmware
