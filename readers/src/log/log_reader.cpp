#include <cstdio>
#include <cstring>
#include <numeric>

#include "cleanslam/readers/bounded_file.hpp"
#include "cleanslam/readers/log_source.hpp"

namespace cleanslam::readers {

namespace lf = hal::log;

const char* to_string(LogDefect d) {
  switch (d) {
    case LogDefect::kBadSync:
      return "bad_sync";
    case LogDefect::kBadLength:
      return "bad_length";
    case LogDefect::kBadCrc:
      return "bad_crc";
    case LogDefect::kTruncated:
      return "truncated";
    case LogDefect::kBadPayload:
      return "bad_payload";
    case LogDefect::kCount:
      break;
  }
  return "?";
}

bool LogReader::open(const std::string& path) {
  auto bytes = read_bounded_bytes(path, kLogFileLimit);
  if (!bytes.ok()) {
    error_ = bytes.error();
    return false;
  }
  return open_bytes(std::move(bytes.value()), path);
}

bool LogReader::open_bytes(std::vector<std::uint8_t> bytes, const std::string& name) {
  bytes_ = std::move(bytes);
  name_ = name;
  records_.clear();
  defects_.fill(0);
  truncated_at_ = 0;
  has_config_ = false;
  config_hash_matches_ = true;
  config_text_ = {};
  files_joined_ = 1;
  join_error_.clear();
  if (bytes_.size() < lf::kFileHeaderSize ||
      !std::equal(lf::kFileMagic.begin(), lf::kFileMagic.end(), bytes_.begin())) {
    error_ = name_ + ": not a cleanslam log (bad magic at offset 0)";
    return false;
  }
  lf::ByteReader header(bytes_.data() + lf::kFileMagic.size(), 8);
  const std::uint32_t version = header.u32();
  if (version != lf::kFormatVersion) {
    error_ = name_ + ": log format version " + std::to_string(version) + ", expected " +
             std::to_string(lf::kFormatVersion);
    return false;
  }
  file_index_ = header.u32();
  index();
  return true;
}

std::uint64_t LogReader::total_defects() const {
  return std::accumulate(defects_.begin(), defects_.end(), std::uint64_t{0});
}

void LogReader::index() {
  const std::size_t n = bytes_.size();
  std::size_t pos = lf::kFileHeaderSize;
  bool in_garbage = false;
  const auto defect = [this](LogDefect d) { ++defects_[static_cast<std::size_t>(d)]; };
  // Steps one byte into garbage; counts one kBadSync per contiguous stretch.
  const auto resync = [&](std::size_t from) {
    pos = from + 1;
    while (pos + 4 <= n) {
      lf::ByteReader r(bytes_.data() + pos, 4);
      if (r.u32() == lf::kRecordSync) {
        return;
      }
      ++pos;
    }
    pos = n;
  };
  std::uint32_t last_index = file_index_;
  while (pos < n) {
    if (n - pos >= lf::kFileHeaderSize &&
        std::memcmp(lf::kFileMagic.data(), bytes_.data() + pos, lf::kFileMagic.size()) == 0) {
      // The next file of a rotated recording joined to this one.
      lf::ByteReader r(bytes_.data() + pos + lf::kFileMagic.size(), 8);
      const std::uint32_t version = r.u32();
      const std::uint32_t index = r.u32();
      if (join_error_.empty() && (version != lf::kFormatVersion || index != last_index + 1)) {
        join_error_ = "at offset " + std::to_string(pos) + " a file with index " +
                      std::to_string(index) + " (format version " + std::to_string(version) +
                      ") follows the file with index " + std::to_string(last_index) +
                      ": a file of the recording is missing or out of order";
      }
      last_index = index;
      ++files_joined_;
      pos += lf::kFileHeaderSize;
      in_garbage = false;
      continue;
    }
    if (n - pos < lf::kRecordHeaderSize) {
      lf::ByteReader r(bytes_.data() + pos, n - pos);
      if (n - pos >= 4 && r.u32() != lf::kRecordSync) {
        defect(LogDefect::kBadSync);
      } else {
        defect(LogDefect::kTruncated);
        truncated_at_ = pos;
      }
      break;
    }
    const lf::RecordHeader h = lf::read_record_header(bytes_.data() + pos);
    if (h.sync != lf::kRecordSync) {
      if (!in_garbage) {
        defect(LogDefect::kBadSync);
      }
      in_garbage = true;
      resync(pos);
      continue;
    }
    if (h.length > lf::kMaxPayload) {
      defect(LogDefect::kBadLength);
      in_garbage = true;
      resync(pos);
      continue;
    }
    if (n - pos - lf::kRecordHeaderSize < h.length) {
      // Either the tail of a file cut short, or a damaged length: look for a later record.
      const std::size_t here = pos;
      resync(pos);
      if (pos >= n) {
        defect(LogDefect::kTruncated);
        truncated_at_ = here;
      } else {
        defect(LogDefect::kBadLength);
      }
      continue;
    }
    if (lf::record_crc(bytes_.data() + pos, h) != h.crc) {
      defect(LogDefect::kBadCrc);
      in_garbage = true;
      resync(pos);
      continue;
    }
    in_garbage = false;
    records_.push_back(LogRecordRef{pos, h.type, h.length});
    if (h.type == lf::RecordType::kConfig && has_config_ && join_error_.empty()) {
      lf::ByteReader r = payload(records_.back());
      if (r.u64() != config_hash_) {
        join_error_ = "the configuration record at offset " + std::to_string(pos) +
                      " differs from the first one: files of different recordings are joined";
      }
    }
    if (h.type == lf::RecordType::kConfig && !has_config_) {
      lf::ByteReader r = payload(records_.back());
      config_hash_ = r.u64();
      const std::size_t text_size = r.remaining();
      const auto* text = reinterpret_cast<const char*>(r.take(text_size));
      if (r.ok()) {
        config_text_ = std::string_view(text, text_size);
        has_config_ = true;
        config_hash_matches_ = lf::fnv1a64(text, text_size) == config_hash_;
      } else {
        defect(LogDefect::kBadPayload);
      }
    }
    pos += lf::kRecordHeaderSize + h.length;
  }
}

}  // namespace cleanslam::readers
