// The replay's log reader (readers::LogReader, LogSource) on any bytes. The first byte picks how
// the rest is read:
//  - bit 0 clear: the rest is the file (after a valid file header when bit 1 is set), so sync
//    words, lengths and checksums are exercised;
//  - bit 0 set: the rest is a list of records (a byte whose low nibble picks the type and whose
//    high nibble is the length's high bits, the length's low byte, the payload), each sealed with
//    a correct checksum, so damaged payloads reach the decoders.
// Every record indexed lies inside the file, and every event the source replays decodes to views
// inside it: an image's last row and the features end within the file's bytes.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "cleanslam/hal/log_format.hpp"
#include "cleanslam/readers/log_source.hpp"

namespace lf = cleanslam::hal::log;
namespace sh = cleanslam::readers;

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_log_reader: %s\n", what);
  std::abort();
}

std::vector<std::uint8_t> file_header() {
  std::vector<std::uint8_t> out(lf::kFileHeaderSize);
  lf::ByteWriter w(out.data(), out.size());
  lf::write_file_header(w);
  return out;
}

std::vector<std::uint8_t> sealed_records(const std::uint8_t* data, std::size_t size) {
  static constexpr std::uint16_t kTypes[] = {1, 2, 3, 4, 5, 6, 16, 17, 18, 0, 7, 0xFFFF};
  std::vector<std::uint8_t> out = file_header();
  std::size_t i = 0;
  while (i + 2 <= size) {
    const auto type = static_cast<lf::RecordType>(kTypes[(data[i] & 0x0FU) % std::size(kTypes)]);
    const std::size_t length =
        std::min<std::size_t>(size - i - 2, ((data[i] >> 4U) << 8U) | data[i + 1]);
    const std::size_t at = out.size();
    out.resize(at + lf::kRecordHeaderSize);
    out.insert(out.end(), data + i + 2, data + i + 2 + length);
    lf::seal_record(out.data() + at, type, static_cast<std::uint32_t>(length));
    i += 2 + length;
  }
  return out;
}

bool inside(const std::uint8_t* p, std::size_t n, const sh::LogReader& reader) {
  const std::uint8_t* begin = reader.record_bytes(sh::LogRecordRef{});
  const std::uint8_t* end = begin + reader.file_size();
  return p >= begin && p <= end && n <= static_cast<std::size_t>(end - p);
}

void check_event(const cleanslam::hal::SensorEvent& e, const sh::LogReader& reader) {
  if (e.kind != cleanslam::hal::SensorEvent::Kind::kFrame) {
    return;
  }
  const cleanslam::hal::CameraFrame& f = e.frame;
  if (f.has_image()) {
    const auto& im = f.image;
    if (im.stride < im.width) {
      fail("an image's stride is below its width");
    }
    const std::size_t span =
        static_cast<std::size_t>(im.height - 1) * static_cast<std::size_t>(im.stride) +
        static_cast<std::size_t>(im.width);
    if (!inside(im.data, span, reader)) {
      fail("an image's rows reach outside the log");
    }
  }
  if (f.feature_count < 0 || f.feature_count > cleanslam::hal::kMaxFeaturesPerFrame ||
      (f.feature_count > 0 && f.features == nullptr)) {
    fail("a frame's feature count is out of range");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) {
    return 0;
  }
  std::vector<std::uint8_t> bytes;
  if ((data[0] & 1U) != 0) {
    bytes = sealed_records(data + 1, size - 1);
  } else {
    if ((data[0] & 2U) != 0) {
      bytes = file_header();
    }
    bytes.insert(bytes.end(), data + 1, data + size);
  }
  sh::LogReader reader;
  if (!reader.open_bytes(bytes, "fuzz.log")) {
    if (reader.error().empty()) {
      fail("a log that does not open without an error message");
    }
    return 0;
  }
  for (const sh::LogRecordRef& r : reader.records()) {
    if (r.offset + lf::kRecordHeaderSize + r.length > reader.file_size()) {
      fail("an indexed record ends beyond the file");
    }
  }
  for (const auto pacing :
       {sh::LogSource::Pacing::kEventTime, sh::LogSource::Pacing::kRecordedTicks}) {
    sh::LogSource source(reader, pacing);
    cleanslam::hal::SensorEvent e;
    std::size_t guard = 0;
    while (!source.exhausted() && guard++ < 4 * reader.records().size() + 8) {
      if (source.read(e)) {
        check_event(e, reader);
      } else if (pacing != sh::LogSource::Pacing::kRecordedTicks || !source.advance_tick()) {
        break;
      }
    }
  }
  return 0;
}
