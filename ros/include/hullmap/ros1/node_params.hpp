#pragma once

#include <limits>
#include <string>

#include <ros/node_handle.h>

#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::ros1 {

/// What hullmap_node does besides the build: its own private parameters.
struct NodeParams {
  std::string frame_id = "map";        ///< ~frame_id: frame of everything published (hullmap's z-up map frame)
  double min_interval = 0.0;           ///< ~min_interval: seconds between the starts of two rebuilds
  std::string output_dir = "hullmap_map";  ///< ~output_dir: where ~save writes (as `hullmap build -o`)
  double radius = 0.25;                ///< ~radius: drone radius for ~check_path, map units
  double occupancy_min_z = -std::numeric_limits<double>::infinity();  ///< ~occupancy_min_z: ~projected_map band
  double occupancy_max_z = std::numeric_limits<double>::infinity();   ///< ~occupancy_max_z
};

/// The build's parameters from the node's private parameters, named as `hullmap build`'s options
/// with '_' for '-' and the same defaults (BuildParams'): ~resolution, ~eps, ~min_pts, ~up, ~scale,
/// ~metric, ~z_min, ~z_max, ~max_range, ~hit, ~miss, ~clamp_min, ~clamp_max, ~occupancy_threshold,
/// ~floor, ~level, ~ceiling, ~concavity, ~flat_gap, ~extension.
/// The one place where node parameters meet BuildParams fields. Throws hullmap::Error naming the
/// parameter ("~up: ...") for a value `hullmap build` would refuse to parse.
pipeline::BuildParams readBuildParams(const ::ros::NodeHandle& private_nh);

/// The node's own parameters (NodeParams), defaults as documented there. Throws hullmap::Error
/// naming the parameter when ~min_interval is negative or ~radius is not > 0.
NodeParams readNodeParams(const ::ros::NodeHandle& private_nh);

}  // namespace hullmap::ros1
