#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "hullmap/pipeline/pipeline.hpp"

/// The live node's parameters, once for both ROS versions: which there are, their defaults, ranges
/// and descriptions (ROS 2 declares its parameters from this table), and the one reading of their
/// values into the build's parameters and the node's own.
namespace hullmap::live {

/// What the node does besides the build: its own parameters.
struct NodeParams {
  std::string frame_id = "map";            ///< frame of everything published (hullmap's z-up map frame)
  double min_interval = 0.0;               ///< seconds between the starts of two rebuilds, >= 0
  std::string output_dir = "hullmap_map";  ///< where save() writes (as `hullmap build -o`)
  double radius = 0.25;                    ///< drone radius for path checks, map units, > 0
  double occupancy_min_z = -std::numeric_limits<double>::infinity();  ///< projected map's height band, map frame
  double occupancy_max_z = std::numeric_limits<double>::infinity();
};

/// Everything a node runs with: the build's parameters (`hullmap build`'s, same defaults) and its own.
struct NodeSettings {
  pipeline::BuildParams build;
  NodeParams node;
};

/// How a parameter's value is written.
enum class ParameterKind {
  kNumber,          ///< a number (an integer is taken as one)
  kOptionalNumber,  ///< a number, or unset ("none" where a value must be given, as in ROS 2)
  kWordOrNumber,    ///< one of `words`, or a number
  kWord,            ///< one of `words` (a number given is refused naming the words; for extension,
                    ///< true and false, as ROS 2's YAML reads on and off, are on and off)
  kText,            ///< any text (`words`, when given, list the accepted ones: parsing checks them)
};

/// A parameter's value as a ROS parameter server holds it.
using ParameterValue = std::variant<bool, std::int64_t, double, std::string>;
/// Values by parameter name; an absent name takes its default.
using ParameterValues = std::map<std::string, ParameterValue>;

/// One parameter of the node.
struct ParameterSpec {
  std::string name;  ///< as the node names it: `hullmap build`'s option with '_' for '-'
  ParameterKind kind = ParameterKind::kNumber;
  ParameterValue default_value;                           ///< `hullmap build`'s default (NodeSettings{})
  std::string description;                                ///< one line: what it is, units, frame
  std::string constraints;                                ///< the values accepted, in words ("> 0, or auto")
  std::vector<std::string> words;                         ///< the words accepted (kWordOrNumber, kWord, kText)
  double min = -std::numeric_limits<double>::infinity();  ///< a number's range (closed unless min_open)
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;  ///< min itself is refused
  bool max_open = false;
  bool whole = false;  ///< only whole numbers
  bool live = true;    ///< a change applies at the next rebuild; false: only at start
};

/// The largest eps, concavity and flat_gap the strict reading takes, in voxels (resolution): the
/// build's work grows steeply with each beyond (docs/ROS.md, Parameters).
inline constexpr int kMaxEpsVoxels = 20;

/// Every parameter of the node, in the order docs/ROS.md lists them.
const std::vector<ParameterSpec>& nodeParameters();

/// The spec of `name`, or nullptr.
const ParameterSpec* findParameter(const std::string& name);

/// "0.25", "auto", "true": a value as text (numbers exactly, %.17g).
std::string valueText(const ParameterValue& value);

/// How strictly readSettings checks.
enum class Checking {
  /// The ROS 1 node's reading: words and the node's own numbers are checked; the build's numbers
  /// are taken as given and a bad one fails each rebuild (naming it).
  kParse,
  /// Also every number against its range, and every value's type: nothing the build would refuse
  /// passes (the ROS 2 node, which rejects a bad value when it is set).
  kStrict,
};

/// The settings of `values` (absent names at their defaults; names not in nodeParameters() are
/// ignored). Throws hullmap::Error::inParameter(prefix + name, why) for the first bad value, so a
/// front end names it its own way ("~eps" in ROS 1, "eps" in ROS 2).
NodeSettings readSettings(const ParameterValues& values, Checking checking, const std::string& prefix = "");

/// The node's names for library parameters in the warnings of the report.json it writes: the
/// parameter's own name ("min_pts"), and "min_pts:=5" with a value, as `ros2 run ... -p` and
/// roslaunch take it (a hullmap::ParameterSpelling).
std::string nodeParameterSpelling(std::string_view field, std::string_view value);

}  // namespace hullmap::live
