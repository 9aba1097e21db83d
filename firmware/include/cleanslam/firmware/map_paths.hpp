#pragma once

#include <string>

namespace cleanslam::firmware {

// The files one map path names. A symbolic link (or a chain of them) at the map path is followed:
// the map is read from and saved to the link's final target, and every companion file sits beside
// that target, so the temporary file is renamed within the target's directory and the link is
// kept. A dangling link names a target that the first save creates. (docs/architecture.md, "Map
// file".)
struct MapPaths {
  std::string path;     // as configured (map.path)
  std::string file;     // the map itself: `path`, or the final target of the link at `path`
  std::string dir;      // file's directory ("." for a bare name)
  std::string tmp;      // `<file>.tmp.<pid>`: this process's temporary file
  std::string refused;  // `<file>.refused`: a file the decoder refused, moved aside
  std::string lock;     // `<file>.lock`: held (flock) by the one process that writes the map
  std::string error;    // why the link could not be followed ("" when it could)

  [[nodiscard]] bool symlink() const { return file != path; }
};

// Follows symbolic links at `path` (relative targets against the link's directory) and names the
// companion files of the result for process `pid`.
[[nodiscard]] MapPaths map_paths(const std::string& path, long pid);

// True for `<base>.tmp` (an earlier version's temporary name) and `<base>.tmp.<digits>`, where
// `base` is the map file's name without its directory.
[[nodiscard]] bool is_map_temporary(const std::string& name, const std::string& base);

}  // namespace cleanslam::firmware
