#include "table.hpp"

#include <cstdio>

namespace cleanslam::tools::paper {

void write_csv(std::ostream& out, const Table& table) {
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    out << (i == 0 ? "" : ",") << table.columns[i];
  }
  out << '\n';
  char buffer[64];
  for (const auto& row : table.rows) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      std::snprintf(buffer, sizeof buffer, "%.6g", row[i]);
      out << (i == 0 ? "" : ",") << buffer;
    }
    out << '\n';
  }
}

}  // namespace cleanslam::tools::paper
