#include "cleanslam/tools/output_paths.hpp"

#include <filesystem>
#include <system_error>

namespace cleanslam::tools {

using readers::Status;

namespace fs = std::filesystem;

namespace {

// True when `path` is `base` or lies below it (both resolved through existing symbolic links).
bool inside(const fs::path& path, const fs::path& base) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  const fs::path b = fs::weakly_canonical(fs::absolute(base, ec), ec);
  auto pi = p.begin();
  for (auto bi = b.begin(); bi != b.end(); ++bi, ++pi) {
    if (bi->empty()) {
      continue;  // trailing separator
    }
    if (pi == p.end() || *pi != *bi) {
      return false;
    }
  }
  return true;
}

Status refuse_inputs(const std::string& out, const std::vector<std::string>& inputs) {
  for (const std::string& in : inputs) {
    if (!in.empty() && inside(out, in)) {
      return Status::failure(out + ": lies inside the input " + in +
                             "; outputs never go into a dataset (choose another folder)");
    }
  }
  return {};
}

Status create_folder(const fs::path& dir) {
  if (dir.empty()) {
    return {};
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    return Status::failure(dir.string() + ": cannot create: " + ec.message());
  }
  return {};
}

}  // namespace

Status prepare_output_dir(const std::string& dir, bool force, const OwnedEntry& owned,
                          const std::vector<std::string>& inputs) {
  if (Status s = refuse_inputs(dir, inputs); !s) {
    return s;
  }
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    return Status::failure(dir + ": exists and is not a folder");
  }
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec)) {
    if (!force) {
      return Status::failure(dir +
                             ": folder is not empty (an earlier run?); choose another folder, or "
                             "add --force to replace this tool's outputs there");
    }
    std::vector<fs::path> doomed;
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
      if (owned && owned(e.path().filename().string())) {
        doomed.push_back(e.path());
      }
    }
    for (const fs::path& p : doomed) {
      fs::remove_all(p, ec);
      if (ec) {
        return Status::failure(p.string() + ": cannot remove: " + ec.message());
      }
    }
  }
  return create_folder(dir);
}

Status prepare_output_file(const std::string& file, bool force,
                           const std::vector<std::string>& inputs) {
  if (Status s = refuse_inputs(file, inputs); !s) {
    return s;
  }
  std::error_code ec;
  if (fs::is_directory(file, ec)) {
    return Status::failure(file + ": is a folder, expected a file name");
  }
  if (fs::exists(file, ec) && !force) {
    return Status::failure(file + ": exists; choose another name, or add --force to replace it");
  }
  return create_folder(fs::path(file).parent_path());
}

}  // namespace cleanslam::tools
