#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace hullmap::io {

/// A map point in map units (metres, or the arbitrary unit of a monocular SLAM map).
using Point = Eigen::Vector3d;
using Points = std::vector<Point>;

/// What a reader (or a filter) did with one input: how many points it read, how many it dropped
/// and why. Reasons are short snake_case keys ("non_finite", "outside_crop", ...) reported verbatim
/// in report.json.
struct InputStats {
  std::string path;
  std::string format;                          ///< "orbslam_echo", "text", "pcd", "ply", "bt", ...
  std::size_t read = 0;                        ///< points found in the file, dropped ones included
  std::map<std::string, std::size_t> dropped;  ///< reason -> count

  std::size_t droppedTotal() const {
    std::size_t n = 0;
    for (const auto& [reason, count] : dropped) n += count;
    return n;
  }
};

/// Points and the account of where they came from.
struct PointSet {
  Points points;
  std::vector<InputStats> inputs;
};

}  // namespace hullmap::io
