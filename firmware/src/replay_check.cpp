#include "cleanslam/firmware/replay_check.hpp"

#include <cstring>
#include <sstream>
#include <vector>

namespace cleanslam::firmware {

namespace lf = hal::log;

namespace {

std::vector<readers::LogRecordRef> outputs(const readers::LogReader& r) {
  std::vector<readers::LogRecordRef> out;
  for (const auto& rec : r.records()) {
    if (lf::is_output(rec.type)) {
      out.push_back(rec);
    }
  }
  return out;
}

const char* type_name(lf::RecordType t) {
  switch (t) {
    case lf::RecordType::kPose:
      return "pose";
    case lf::RecordType::kUpdate:
      return "update";
    case lf::RecordType::kFusion:
      return "fusion";
    default:
      return "record";
  }
}

std::string describe(const readers::LogReader& r, const readers::LogRecordRef& rec) {
  std::ostringstream s;
  lf::ByteReader p = r.payload(rec);
  s << type_name(rec.type) << " at offset " << rec.offset << " (t_ns " << p.i64() << ")";
  return s.str();
}

}  // namespace

OutputComparison compare_outputs(const readers::LogReader& original,
                                 const readers::LogReader& replayed, bool original_truncated) {
  const auto a = outputs(original);
  const auto b = outputs(replayed);
  OutputComparison c;
  c.original_outputs = a.size();
  c.replayed_outputs = b.size();
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) {
    const bool same =
        a[i].type == b[i].type && a[i].length == b[i].length &&
        std::memcmp(original.record_bytes(a[i]) + lf::kRecordHeaderSize,
                    replayed.record_bytes(b[i]) + lf::kRecordHeaderSize, a[i].length) == 0;
    if (!same) {
      c.first_difference = i;
      c.original_offset = a[i].offset;
      c.description = "output record " + std::to_string(i) + " differs: recorded " +
                      describe(original, a[i]) + ", replayed " + describe(replayed, b[i]);
      return c;
    }
  }
  if (a.size() != b.size() && !(original_truncated && b.size() > a.size())) {
    c.first_difference = n;
    c.original_offset = n < a.size() ? a[n].offset : original.file_size();
    c.description = "output counts differ: recorded " + std::to_string(a.size()) + ", replayed " +
                    std::to_string(b.size()) + "; first unmatched is " +
                    (n < a.size() ? describe(original, a[n]) : describe(replayed, b[n]));
    return c;
  }
  c.identical = true;
  return c;
}

}  // namespace cleanslam::firmware
