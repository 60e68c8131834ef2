#include "hullmap/ros1/node_params.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

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

/// A parameter that is a number or one of `words` (as "auto"): the word, or the number as text;
/// `fallback` when the parameter is not set.
std::string wordOrNumber(const ::ros::NodeHandle& nh, const std::string& name, const std::string& fallback) {
  if (!nh.hasParam(name)) return fallback;
  std::string text;
  if (nh.getParam(name, text)) return text;
  double number = 0.0;
  if (nh.getParam(name, number)) {
    char text_of[32];
    std::snprintf(text_of, sizeof text_of, "%.17g", number);  // exact: read back by std::stod
    return text_of;
  }
  int whole = 0;
  if (nh.getParam(name, whole)) return std::to_string(whole);
  throw Error::inParameter("~" + name, "expected a number or a word such as auto");
}

double numberParam(const std::string& name, const std::string& text) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value)) throw Error::inParameter("~" + name, "expected a number, got '" + text + "'");
  return value;
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
  // eps and min_pts: a number, or "auto" (the default: chosen from the map, as hullmap build).
  const std::string eps = wordOrNumber(nh, "eps", "auto");
  if (eps != "auto") p.eps = numberParam("eps", eps);
  const std::string min_pts = wordOrNumber(nh, "min_pts", "auto");
  if (min_pts != "auto") {
    const double n = numberParam("min_pts", min_pts);
    if (n != std::floor(n) || n < 1 || n > 1e9) throw Error::inParameter("~min_pts", "expected a whole number >= 1 or auto");
    p.min_pts = int(n);
  }
  // floor / ceiling: auto, none or a height; concavity: default, none or a length (map units).
  p.floor = mapper::parsePlaneSetting("~floor", wordOrNumber(nh, "floor", "auto"));
  p.ceiling = mapper::parsePlaneSetting("~ceiling", wordOrNumber(nh, "ceiling", "none"));
  // level: auto (a camera's frame: ORB-SLAM's map markers, or ~up other than z), on or off.
  std::string level = "auto";
  nh.param("level", level, level);
  if (level == "on" || level == "off") {
    p.level = level == "on" ? pipeline::Level::kOn : pipeline::Level::kOff;
  } else if (level != "auto") {
    throw Error::inParameter("~level", "expected auto, on or off, got '" + level + "'");
  }
  const std::string concavity = wordOrNumber(nh, "concavity", "default");
  if (concavity == "none") {
    p.convex_parts.reset();
  } else if (concavity != "default") {
    const double t = numberParam("concavity", concavity);
    if (!(t > 0.0)) throw Error::inParameter("~concavity", "must be > 0, default or none");
    p.convex_parts->concavity = t;
  }
  // flat_gap: auto (the eps used), 0 (off) or a length; a number cannot apply without convex parts.
  const std::string flat_gap = wordOrNumber(nh, "flat_gap", "auto");
  if (flat_gap != "auto") {
    const double g = numberParam("flat_gap", flat_gap);
    if (!(g >= 0.0)) throw Error::inParameter("~flat_gap", "must be >= 0 (0: off) or auto, got " + flat_gap);
    if (!p.convex_parts)
      throw Error::inParameter("~flat_gap", "applies only to convex parts, and ~concavity none makes one hull per "
                                             "cluster; leave it auto");
    p.convex_parts->flat_gap = g;
  }
  // extension: auto (on when min_pts is auto), on or off, as `hullmap build --extension`.
  const std::string extension = wordOrNumber(nh, "extension", "auto");
  if (extension == "on" || extension == "off") {
    p.extension = extension == "on";
  } else if (extension != "auto") {
    throw Error::inParameter("~extension", "expected auto, on or off, got '" + extension + "'");
  }
  std::string up = pipeline::upAxisText(p.frame.up);
  nh.param("up", up, up);
  p.frame.up = parsed("up", up, mapper::parseUpAxis);
  nh.param("scale", p.frame.scale, p.frame.scale);
  std::string metric = clustering::toString(p.metric);
  nh.param("metric", metric, metric);
  p.metric = parsed("metric", metric, clustering::parseMetric);
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
