#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace cleanslam::tools::paper {

struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::vector<std::string> notes;  // for stderr
};

void write_csv(std::ostream& out, const Table& table);

}  // namespace cleanslam::tools::paper
