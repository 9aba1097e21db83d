#pragma once

#include <cstdint>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cleanslam/readers/result.hpp"

namespace cleanslam::readers {

// One data row of a dataset CSV file; its conversions fail with "file:line: column: ...".
class CsvRow {
 public:
  CsvRow(const std::string& file, int line, const std::vector<std::string>& columns,
         const std::vector<std::string_view>& fields)
      : file_(&file), line_(line), columns_(&columns), fields_(&fields) {}

  [[nodiscard]] int line() const { return line_; }
  [[nodiscard]] std::size_t size() const { return fields_->size(); }
  [[nodiscard]] std::string_view text(std::size_t i) const { return (*fields_)[i]; }
  [[nodiscard]] Result<std::int64_t> integer(std::size_t i) const;
  [[nodiscard]] Result<double> number(std::size_t i) const;  // finite only
  // "file:line: column: message"
  [[nodiscard]] std::string fail(std::size_t i, std::string_view message) const;
  // "file:line: message"
  [[nodiscard]] std::string fail_row(std::string_view message) const;

 private:
  const std::string* file_;
  int line_;
  const std::vector<std::string>* columns_;
  const std::vector<std::string_view>* fields_;
};

struct CsvSpec {
  std::vector<std::string> columns;           // required, in order
  std::vector<std::string> optional_columns;  // may follow, all or none
  // A last line without a line end (a file cut short: its last value may be cut too) is skipped
  // with a warning here; without `warnings` it is an error.
  std::vector<std::string>* warnings = nullptr;
};

// Reads a CSV file of the dataset format (the rules of read_csv below) one row at a time, holding
// one line in memory. Not movable: the rows it hands out point into it.
class CsvReader {
 public:
  CsvReader() = default;
  CsvReader(const CsvReader&) = delete;
  CsvReader& operator=(const CsvReader&) = delete;

  // Opens the file and checks its header.
  Status open(const std::string& path, const CsvSpec& spec);
  // The next data row, valid until the next call; none at the end of the file or at an error
  // (then error() says which).
  std::optional<CsvRow> next();
  [[nodiscard]] const std::string& error() const { return error_; }
  [[nodiscard]] const std::vector<std::string>& columns() const { return columns_; }

 private:
  std::string path_;
  std::vector<std::string>* warnings_ = nullptr;
  std::ifstream in_;
  std::string line_;
  std::vector<std::string_view> fields_;
  std::vector<std::string> columns_;
  int line_no_ = 1;
  bool done_ = true;
  std::string error_;
};

// Reads a CSV file of the dataset format: one header line "#col1,col2,..." matching `spec`,
// then comma-separated rows (blank lines ignored), each with as many fields as the header.
// Calls `on_row` for each row; stops at the first error (from the file or from `on_row`, which
// returns an empty string to continue or an error message to stop). `columns_out` receives the
// columns the header named.
Status read_csv(const std::string& path, const CsvSpec& spec,
                const std::function<std::string(const CsvRow&)>& on_row,
                std::vector<std::string>* columns_out = nullptr);

// Splits one CSV line on commas, trimming spaces and a trailing '\r'.
void split_csv_line(std::string_view line, std::vector<std::string_view>& out);

bool parse_int64(std::string_view s, std::int64_t& out);
bool parse_finite_double(std::string_view s, double& out);

}  // namespace cleanslam::readers
