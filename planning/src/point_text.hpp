#pragma once

#include <Eigen/Core>
#include <sstream>
#include <string>

namespace hullmap::planning::detail {

/// A point as messages print it: "(x, y, z)", six significant digits.
inline std::string pointText(const Eigen::Vector3d& p) {
  std::ostringstream s;
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

}  // namespace hullmap::planning::detail
