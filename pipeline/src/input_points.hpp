#pragma once

// Reading the inputs' points, apart from the rest of the pipeline: `hullmap cluster` links this
// file alone, without the octree, hull and collision code (and FCL) that build() needs.

#include <filesystem>
#include <string>
#include <vector>

#include "hullmap/core/error.hpp"

namespace hullmap::pipeline {

/// The error of inputs that hold no point: "<input>, <input>: no points".
Error noPoints(const std::vector<std::string>& inputs);

/// The inputs' paths as strings, in order.
inline std::vector<std::string> pathStrings(const std::vector<std::filesystem::path>& paths) {
  std::vector<std::string> strings;
  for (const auto& p : paths) strings.push_back(p.string());
  return strings;
}

}  // namespace hullmap::pipeline
