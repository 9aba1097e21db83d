#pragma once

#include <string>

namespace cleanslam::tools::paper {

// plot_paper.py: CLEANSLAM_PLOT_SCRIPT, the source tree, beside the executable, or the installed
// share directory. Empty when none exists.
std::string find_plot_script(const char* argv0);

// Runs $CLEANSLAM_PYTHON (default python3) SCRIPT FIGURE CSV PNG; returns its exit status (127 when
// it could not start), and a message naming what failed in error.
int run_plot_script(const std::string& script, const std::string& figure, const std::string& csv,
                    const std::string& png, std::string& error);

}  // namespace cleanslam::tools::paper
