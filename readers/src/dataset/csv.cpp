#include "cleanslam/readers/csv.hpp"

#include "cleanslam/readers/bounded_file.hpp"

#include <charconv>
#include <cmath>

namespace cleanslam::readers {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) {
    s.remove_prefix(1);
  }
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return s;
}

std::string quote(std::string_view s) {
  constexpr std::size_t kMax = 40;
  std::string out = "\"";
  out += s.size() > kMax ? std::string(s.substr(0, kMax)) + "..." : std::string(s);
  out += '"';
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const std::string& s : v) {
    if (!out.empty()) {
      out += ',';
    }
    out += s;
  }
  return out;
}

}  // namespace

bool parse_int64(std::string_view s, std::int64_t& out) {
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
  }
  if (s.empty()) {
    return false;
  }
  const char* end = s.data() + s.size();
  auto [ptr, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc() && ptr == end;
}

bool parse_finite_double(std::string_view s, double& out) {
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
  }
  if (s.empty()) {
    return false;
  }
  const char* end = s.data() + s.size();
  auto [ptr, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc() && ptr == end && std::isfinite(out);
}

void split_csv_line(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      out.push_back(trim(line.substr(start)));
      return;
    }
    out.push_back(trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

Result<std::int64_t> CsvRow::integer(std::size_t i) const {
  std::int64_t v = 0;
  if (!parse_int64(text(i), v)) {
    return Result<std::int64_t>::failure(fail(i, "expected an integer, got " + quote(text(i))));
  }
  return v;
}

Result<double> CsvRow::number(std::size_t i) const {
  double v = 0.0;
  if (!parse_finite_double(text(i), v)) {
    return Result<double>::failure(fail(i, "expected a finite number, got " + quote(text(i))));
  }
  return v;
}

std::string CsvRow::fail(std::size_t i, std::string_view message) const {
  const std::string column = i < columns_->size() ? (*columns_)[i] : "column " + std::to_string(i);
  return *file_ + ":" + std::to_string(line_) + ": " + column + ": " + std::string(message);
}

std::string CsvRow::fail_row(std::string_view message) const {
  return *file_ + ":" + std::to_string(line_) + ": " + std::string(message);
}

Status CsvReader::open(const std::string& path, const CsvSpec& spec) {
  path_ = path;
  warnings_ = spec.warnings;
  line_no_ = 1;
  done_ = true;
  error_.clear();
  columns_.clear();
  in_.close();
  in_.clear();
  Status bounded = check_bounded_file(path, kCsvFileLimit);
  if (!bounded) {
    return bounded;
  }
  in_.open(path, std::ios::binary);
  if (!in_) {
    return Status::failure(path + ": cannot open file");
  }
  if (!std::getline(in_, line_)) {
    return Status::failure(path + ":1: empty file, expected a header");
  }
  const std::string_view header = trim(line_);
  std::string expected(1, '#');
  expected += join(spec.columns);
  if (header.empty() || header.front() != '#') {
    return Status::failure(path + ":1: expected the header \"" + expected + "\", got " +
                           quote(header));
  }
  split_csv_line(header.substr(1), fields_);
  for (std::string_view f : fields_) {
    columns_.emplace_back(f);
  }
  std::vector<std::string> with_optional = spec.columns;
  with_optional.insert(with_optional.end(), spec.optional_columns.begin(),
                       spec.optional_columns.end());
  if (columns_ != spec.columns && (spec.optional_columns.empty() || columns_ != with_optional)) {
    std::string msg = path + ":1: expected the header \"" + expected + "\"";
    if (!spec.optional_columns.empty()) {
      msg += " (optionally followed by ,";
      msg += join(spec.optional_columns);
      msg += ")";
    }
    return Status::failure(msg + ", got " + quote(header));
  }
  done_ = false;
  return Status();
}

std::optional<CsvRow> CsvReader::next() {
  while (!done_ && std::getline(in_, line_)) {
    ++line_no_;
    const std::string_view body = trim(line_);
    if (body.empty()) {
      continue;
    }
    if (in_.eof()) {
      done_ = true;
      const std::string cut = path_ + ":" + std::to_string(line_no_) +
                              ": the last line has no line end: the file was cut short";
      if (warnings_ == nullptr) {
        error_ = cut;
      } else {
        warnings_->push_back(cut + "; its last row is skipped");
      }
      return std::nullopt;
    }
    split_csv_line(body, fields_);
    CsvRow row(path_, line_no_, columns_, fields_);
    if (fields_.size() != columns_.size()) {
      done_ = true;
      error_ = row.fail_row("expected " + std::to_string(columns_.size()) + " fields, got " +
                            std::to_string(fields_.size()));
      return std::nullopt;
    }
    return row;
  }
  if (!done_ && in_.bad()) {
    error_ = path_ + ": read error";
  }
  done_ = true;
  return std::nullopt;
}

Status read_csv(const std::string& path, const CsvSpec& spec,
                const std::function<std::string(const CsvRow&)>& on_row,
                std::vector<std::string>* columns_out) {
  CsvReader reader;
  Status s = reader.open(path, spec);
  if (!s) {
    return s;
  }
  if (columns_out != nullptr) {
    *columns_out = reader.columns();
  }
  while (const std::optional<CsvRow> row = reader.next()) {
    std::string err = on_row(*row);
    if (!err.empty()) {
      return Status::failure(std::move(err));
    }
  }
  if (!reader.error().empty()) {
    return Status::failure(reader.error());
  }
  return Status();
}

}  // namespace cleanslam::readers
