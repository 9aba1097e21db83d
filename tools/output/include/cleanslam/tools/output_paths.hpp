#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cleanslam/readers/result.hpp"

namespace cleanslam::tools {

// Which entries of an output folder a tool wrote itself (and may delete under --force).
using OwnedEntry = std::function<bool(const std::string& name)>;

// Makes `dir` ready for a tool's outputs, creating it and its parents. Refused, with a message
// naming the folder, when it is or lies inside one of `inputs` (a dataset is never written
// into), or when it holds anything and `force` is false. With `force` the entries `owned` names
// are deleted first, so no output of an earlier run stays beside the new ones.
readers::Status prepare_output_dir(const std::string& dir, bool force, const OwnedEntry& owned,
                                   const std::vector<std::string>& inputs);

// Makes `file` ready to be written: refused when it exists and `force` is false, or when it lies
// inside one of `inputs`; its folder is created.
readers::Status prepare_output_file(const std::string& file, bool force,
                                    const std::vector<std::string>& inputs);

}  // namespace cleanslam::tools
