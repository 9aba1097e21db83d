#include "cleanslam/firmware/map_paths.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

namespace cleanslam::firmware {

namespace {

// As many links as the kernel follows in one path lookup (Linux's MAXSYMLINKS).
constexpr int kMaxLinks = 40;

// `path`'s final target; sets `error` (and returns `path`) on a loop or an unreadable link.
std::string follow_links(const std::string& path, std::string& error) {
  namespace fs = std::filesystem;
  fs::path p(path);
  for (int hops = 0; hops <= kMaxLinks; ++hops) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) {
      return p.string();
    }
    std::vector<char> target(static_cast<std::size_t>(std::max<off_t>(st.st_size, 255)) + 1);
    const ssize_t n = ::readlink(p.c_str(), target.data(), target.size());
    if (n < 0 || static_cast<std::size_t>(n) >= target.size()) {
      error = "cannot read the symbolic link " + p.string() + ": " +
              (n < 0 ? std::strerror(errno) : "it changed while being read");
      return path;
    }
    const fs::path next(std::string(target.data(), static_cast<std::size_t>(n)));
    p = next.is_absolute() ? next : p.parent_path() / next;
  }
  error = "more than " + std::to_string(kMaxLinks) + " symbolic links (a loop?)";
  return path;
}

}  // namespace

MapPaths map_paths(const std::string& path, long pid) {
  MapPaths m;
  m.path = path;
  m.file = follow_links(path, m.error);
  const std::filesystem::path parent = std::filesystem::path(m.file).parent_path();
  m.dir = parent.empty() ? std::string(".") : parent.string();
  m.tmp = m.file + ".tmp." + std::to_string(pid);
  m.refused = m.file + ".refused";
  m.lock = m.file + ".lock";
  return m;
}

bool is_map_temporary(const std::string& name, const std::string& base) {
  const std::string stem = base + ".tmp";
  if (name.compare(0, stem.size(), stem) != 0) {
    return false;
  }
  if (name.size() == stem.size()) {
    return true;
  }
  if (name[stem.size()] != '.' || name.size() == stem.size() + 1) {
    return false;
  }
  return std::all_of(name.begin() + static_cast<std::ptrdiff_t>(stem.size()) + 1, name.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
}

}  // namespace cleanslam::firmware
