#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hullmap {

/// A warning from a library: what a result leaves out or misstates, as a numbered code with the
/// values it speaks of. Libraries give these and never text; a front end puts one into words with
/// warningText and its own names for the parameters (the command line "--min-pts", the ROS node
/// "min_pts", Python "min_pts=").
struct Warning {
  /// The codes, numbered for good: a number is never reused for another warning.
  enum class Code : int {
    kEpsBelowResolution = 1,           ///< eps < resolution, xyz metric: no two voxels neighbours
    kEpsBelowResolutionInColumns = 2,  ///< eps < resolution, xy metric: only a column's voxels
    kNoObstacle = 3,                   ///< voxels occupied, every one noise to DBSCAN
    kMostlyNoise = 4,                  ///< more than half the occupied voxels noise
    kKeptFloorTilted = 5,              ///< the floor found is tilted and the map kept its input frame
    kMapLooksTilted = 6,               ///< no floor used, yet the main floor-like plane is tilted
    kOrbSlamFrame = 7,                 ///< an ORB-SLAM input read with the up axis left at z
    kCheckNoObstacle = 8,              ///< a hull check against a build with no obstacle
    kCheckMostlyNoise = 9,             ///< a hull check against a build whose voxels are mostly noise
    kSparseForResolution = 10,         ///< the map's points lie many voxels apart: a coarser resolution fits
  };

  Code code;
  /// The values the warning speaks of, by name (the names each code uses are listed in
  /// docs/LIBRARY.md): counts, eps, resolution, shares (0..1), degrees.
  std::vector<std::pair<std::string, double>> numbers;
  /// The file or axis it names ("" when none): the input for kOrbSlamFrame, the up axis for
  /// kMapLooksTilted.
  std::string subject;

  /// The value named `name`; 0 when the warning has none by that name.
  double number(std::string_view name) const;
};

/// How a front end names a parameter in its text: `field` is the library's name for it (a field of
/// the params structs: "eps", "min_pts", "z_min", "level", "against"), `value` a value to give it
/// ("" for the name alone).
using ParameterSpelling = std::function<std::string(std::string_view field, std::string_view value)>;

/// The library's own names: "min_pts", and "min_pts=5" with a value.
std::string fieldSpelling(std::string_view field, std::string_view value);

/// The warning in one line, each parameter named by `spell`.
std::string warningText(const Warning& warning, const ParameterSpelling& spell = fieldSpelling);

/// The code's name, as report.json and the docs give it: "mostly_noise".
const char* warningName(Warning::Code code);

}  // namespace hullmap
