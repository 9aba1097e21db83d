#include "log_reports.hpp"

#include <cstdio>
#include <filesystem>

namespace cleanslam::firmware {

namespace {

// Suffix k of a rotated log's name (LOG.k), or 0.
int rotation_suffix(const std::string& path, std::string& base) {
  const std::size_t dot = path.find_last_of('.');
  base = path;
  if (dot == std::string::npos || dot + 1 == path.size() ||
      path.find_first_not_of("0123456789", dot + 1) != std::string::npos || path.size() - dot > 6) {
    return 0;
  }
  base = path.substr(0, dot);
  return std::stoi(path.substr(dot + 1));
}

}  // namespace

void report_log_source(const readers::LogSource& source, const std::string& name, Loop* loop) {
  for (const std::string& m : source.messages()) {
    std::fprintf(stderr, "cleanslam: warning: %s\n", m.c_str());
  }
  const std::uint64_t n =
      source.payload_defects() + source.stamps_refused() + source.out_of_place();
  if (n > source.messages().size()) {
    std::fprintf(stderr, "cleanslam: warning: %s: %llu more record(s) skipped the same ways\n",
                 name.c_str(), static_cast<unsigned long long>(n - source.messages().size()));
  }
  if (loop != nullptr) {
    loop->count(Reject::kCorruptRecord, source.payload_defects(), true);
    loop->count(Reject::kTimeJump, source.stamps_refused(), true);
    loop->count(Reject::kOutOfOrder, source.out_of_place(), true);
  }
}

bool config_hash_checked(const readers::LogReader& reader, bool fatal) {
  if (!reader.has_config() || reader.config_hash_matches()) {
    return true;
  }
  std::fprintf(stderr,
               "cleanslam: %s: %s: the configuration record's hash (0x%016llx) is not that of its "
               "text: the configuration was altered after recording%s\n",
               fatal ? "error" : "warning", reader.name().c_str(),
               static_cast<unsigned long long>(reader.config_hash()),
               fatal ? "; a replay with it would not be the recorded run" : "");
  return !fatal;
}

bool replayable_alone(const readers::LogReader& log, const std::string& path) {
  if (!log.join_error().empty()) {
    std::fprintf(stderr, "cleanslam: error: %s: %s: cannot replay\n", path.c_str(),
                 log.join_error().c_str());
    return false;
  }
  if (log.file_index() == 0) {
    return true;
  }
  std::string base;
  const int k = rotation_suffix(path, base);
  std::string files;
  std::string missing;
  for (int i = k + static_cast<int>(log.file_index()); i >= 1; --i) {
    const std::string name = base + "." + std::to_string(i);
    files += name + " ";
    std::error_code ec;
    if (missing.empty() && !std::filesystem::exists(name, ec)) {
      missing = name;
    }
  }
  files += base;
  std::fprintf(stderr,
               "cleanslam: error: %s is file %u of a rotated recording (its header's file index; "
               "0 is the file the run began in): it continues a run whose estimator state is not "
               "in it, so its outputs cannot be reproduced alone.\n",
               path.c_str(), log.file_index());
  if (!missing.empty()) {
    std::fprintf(stderr,
                 "cleanslam: %s, which the run's start needs, does not exist (deleted by "
                 "rotation: recorder.max_files): this recording cannot be replayed bit for bit; "
                 "--log runs it afresh from its first record\n",
                 missing.c_str());
    return false;
  }
  std::fprintf(stderr,
               "cleanslam: join the files oldest first and replay the join:\n  cat %s > "
               "joined.log && cleanslam --replay joined.log\n",
               files.c_str());
  return false;
}

void report_log_defects(const readers::LogReader& reader, Loop* loop) {
  if (reader.total_defects() == 0) {
    return;
  }
  for (int d = 0; d < static_cast<int>(readers::LogDefect::kCount); ++d) {
    const auto defect = static_cast<readers::LogDefect>(d);
    if (reader.defects(defect) > 0) {
      std::fprintf(stderr, "cleanslam: warning: %s: %llu %s record(s) skipped\n",
                   reader.name().c_str(), static_cast<unsigned long long>(reader.defects(defect)),
                   readers::to_string(defect));
    }
  }
  if (reader.defects(readers::LogDefect::kTruncated) > 0) {
    std::fprintf(stderr,
                 "cleanslam: warning: %s is truncated at byte %zu: replaying up to its last whole "
                 "record\n",
                 reader.name().c_str(), reader.truncated_at());
  }
  if (loop != nullptr) {
    loop->count(Reject::kCorruptRecord, reader.total_defects(), true);
  }
}

}  // namespace cleanslam::firmware
