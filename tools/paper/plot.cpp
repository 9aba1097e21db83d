#include "plot.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <vector>

extern char** environ;

namespace cleanslam::tools::paper {

std::string find_plot_script(const char* argv0) {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("CLEANSLAM_PLOT_SCRIPT"); env != nullptr && *env != '\0') {
    candidates.emplace_back(env);
  }
  candidates.emplace_back(fs::path(CLEANSLAM_SOURCE_DIR) / "tools" / "plot" / "plot_paper.py");
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) {
    exe = fs::absolute(argv0, ec);
  }
  if (!exe.empty()) {
    const fs::path dir = exe.parent_path();
    candidates.push_back(dir / "plot_paper.py");
    candidates.push_back(dir.parent_path() / "share" / "cleanslam" / "plot_paper.py");
  }
  for (const auto& candidate : candidates) {
    if (fs::is_regular_file(candidate, ec)) {
      return candidate.string();
    }
  }
  return {};
}

int run_plot_script(const std::string& script, const std::string& figure, const std::string& csv,
                    const std::string& png, std::string& error) {
  const char* env = std::getenv("CLEANSLAM_PYTHON");
  std::string python = env != nullptr && *env != '\0' ? env : "python3";
  std::vector<std::string> args{python, script, figure, csv, png};
  std::vector<char*> argv;
  for (auto& a : args) {
    argv.push_back(a.data());
  }
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ);
  if (rc != 0) {
    error = "cannot start " + python + ": " + std::string(std::strerror(rc));
    return 127;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      error = "waitpid: " + std::string(std::strerror(errno));
      return 127;
    }
  }
  if (!WIFEXITED(status)) {
    error = script + " was terminated by a signal";
    return 128;
  }
  if (WEXITSTATUS(status) != 0) {
    error = script + " exited with status " + std::to_string(WEXITSTATUS(status));
  }
  return WEXITSTATUS(status);
}

}  // namespace cleanslam::tools::paper
