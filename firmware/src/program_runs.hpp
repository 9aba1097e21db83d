#pragma once

#include "program_args.hpp"

// The two ways `cleanslam` runs; each returns the program's exit status.
namespace cleanslam::firmware {

// A run on the robot's drivers, a dataset or a log, with the outputs the configuration names.
int run_normal(const Args& args);
// --replay: a recorded log through the loop at its recorded iterations, outputs compared.
int run_replay(const Args& args);

}  // namespace cleanslam::firmware
