#pragma once

#include <ros/node_handle.h>

#include "hullmap/live/node_params.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::ros1 {

/// What hullmap_node does besides the build: its own private parameters (~frame_id, ~min_interval,
/// ~output_dir, ~radius, ~occupancy_min_z, ~occupancy_max_z), as live::NodeParams documents them.
using NodeParams = live::NodeParams;

/// Every parameter of live::nodeParameters() that is set in the node's private namespace, as
/// hullmap_node has always read it: a number parameter only when set as a number, a text one only
/// when set as text (anything else is left at its default), a word-or-number one as either (else
/// hullmap::Error "~name: expected a number or a word such as auto").
live::ParameterValues readParameterValues(const ::ros::NodeHandle& private_nh);

/// The node's settings from its private parameters (live::readSettings with Checking::kParse,
/// errors naming "~name"): the build's parameters are `hullmap build`'s options with '_' for '-'
/// and the same defaults (~resolution, ~eps, ~min_pts, ~up, ~scale, ~metric, ~z_min, ~z_max,
/// ~max_range, ~hit, ~miss, ~clamp_min, ~clamp_max, ~occupancy_threshold, ~floor, ~ceiling,
/// ~concavity, ~flat_gap, ~extension). Throws hullmap::Error naming the parameter ("~up: ...") for a
/// value `hullmap build` would refuse to parse, a negative ~min_interval or a ~radius not > 0.
live::NodeSettings readSettings(const ::ros::NodeHandle& private_nh);

/// readSettings(private_nh).build.
pipeline::BuildParams readBuildParams(const ::ros::NodeHandle& private_nh);

/// readSettings(private_nh).node.
NodeParams readNodeParams(const ::ros::NodeHandle& private_nh);

}  // namespace hullmap::ros1
