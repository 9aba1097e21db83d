#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cleanslam/firmware/program.hpp"

// Firmware logs for the calibration tests: the firmware (in process, as `cleanslam --dataset
// DIR --record LOG`) run on a simulated recording, so that the log holds the records that
// crossed the hal boundary, as one recorded on the robot does.
namespace cleanslam::calibrate_test {

inline void record_log(const std::string& dataset, const std::string& log,
                       const std::vector<std::string>& sets = {}) {
  std::vector<std::string> args{"cleanslam", "--dataset", dataset, "--record", log};
  for (const std::string& s : sets) {
    args.emplace_back("--set");
    args.push_back(s);
  }
  std::vector<char*> argv;
  for (std::string& a : args) {
    argv.push_back(a.data());
  }
  ASSERT_EQ(firmware::program_main(static_cast<int>(argv.size()), argv.data()), 0)
      << "cleanslam --dataset " << dataset << " --record " << log;
}

}  // namespace cleanslam::calibrate_test
