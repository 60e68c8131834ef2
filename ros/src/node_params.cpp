#include "hullmap/ros1/node_params.hpp"

#include <cmath>

#include "hullmap/core/error.hpp"

namespace hullmap::ros1 {
namespace {

/// A private parameter parsed by `parse`, its errors named "~name: ..." whatever the parser called it.
template <typename Parse>
auto parsed(const std::string& name, const std::string& text, Parse&& parse) {
  try {
    return parse(text);
  } catch (const Error& e) {
    throw Error::inParameter("~" + name, e.detail());
  }
}

void optionalParam(const ::ros::NodeHandle& nh, const std::string& name, std::optional<double>& value) {
  double v = 0.0;
  if (nh.getParam(name, v)) value = v;
}

}  // namespace

pipeline::BuildParams readBuildParams(const ::ros::NodeHandle& nh) {
  pipeline::BuildParams p;  // `hullmap build`'s defaults
  nh.param("resolution", p.octree.resolution, p.octree.resolution);
  nh.param("max_range", p.octree.max_range, p.octree.max_range);
  nh.param("hit", p.octree.sensor.hit, p.octree.sensor.hit);
  nh.param("miss", p.octree.sensor.miss, p.octree.sensor.miss);
  nh.param("clamp_min", p.octree.sensor.clamp_min, p.octree.sensor.clamp_min);
  nh.param("clamp_max", p.octree.sensor.clamp_max, p.octree.sensor.clamp_max);
  nh.param("occupancy_threshold", p.octree.sensor.occupancy_threshold, p.octree.sensor.occupancy_threshold);
  nh.param("eps", p.dbscan.eps, p.dbscan.eps);
  nh.param("min_pts", p.dbscan.min_pts, p.dbscan.min_pts);
  std::string up = pipeline::upAxisText(p.frame.up);
  nh.param("up", up, up);
  p.frame.up = parsed("up", up, mapper::parseUpAxis);
  nh.param("scale", p.frame.scale, p.frame.scale);
  std::string metric = clustering::toString(p.dbscan.metric);
  nh.param("metric", metric, metric);
  p.dbscan.metric = parsed("metric", metric, clustering::parseMetric);
  optionalParam(nh, "z_min", p.filters.z_min);
  optionalParam(nh, "z_max", p.filters.z_max);
  return p;
}

NodeParams readNodeParams(const ::ros::NodeHandle& nh) {
  NodeParams p;
  nh.param("frame_id", p.frame_id, p.frame_id);
  nh.param("min_interval", p.min_interval, p.min_interval);
  nh.param("output_dir", p.output_dir, p.output_dir);
  nh.param("radius", p.radius, p.radius);
  nh.param("occupancy_min_z", p.occupancy_min_z, p.occupancy_min_z);
  nh.param("occupancy_max_z", p.occupancy_max_z, p.occupancy_max_z);
  if (!(p.min_interval >= 0.0) || !std::isfinite(p.min_interval)) {
    throw Error::inParameter("~min_interval", "must be finite and >= 0 seconds, got " + std::to_string(p.min_interval));
  }
  if (!(p.radius > 0.0) || !std::isfinite(p.radius)) {
    throw Error::inParameter("~radius", "must be finite and > 0, got " + std::to_string(p.radius));
  }
  return p;
}

}  // namespace hullmap::ros1
