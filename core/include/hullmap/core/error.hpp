#pragma once

#include <stdexcept>
#include <string>

namespace hullmap {

/// The one exception hullmap's public API throws. Its message names the file and line, or the
/// parameter, at fault: "maps/a.pcd:12: expected 3 numbers, got 2".
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace hullmap
