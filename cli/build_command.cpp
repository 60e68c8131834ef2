#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/mapper/level_check.hpp"
#include "hullmap/mapper/output_dir.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "option_checks.hpp"
#ifdef HULLMAP_HAS_ROSBAG
#include "hullmap/ros1/bag_map.hpp"
#endif

namespace hullmap::cli {
namespace {

/// `hullmap build`'s options as typed; strings still to parse.
struct BuildOptions {
  std::vector<std::string> inputs;
  std::string output_dir = "out";
  bool make_parents = false;  ///< -p: create missing parents of output_dir (mkdir -p)
  std::optional<std::string> trajectory;
  std::optional<std::string> origin;  ///< "x,y,z"
  std::string up = "z";
  double scale = 1.0;
  std::optional<std::string> crop;    ///< "x0,y0,z0,x1,y1,z1"
  std::optional<double> z_min;
  std::optional<double> z_max;
  std::string metric = "xyz";
  std::optional<std::string> topic;  ///< the input is a ROS1 bag: its map topic
  std::optional<std::string> trajectory_topic;  ///< and its keyframe poses' topic
  pipeline::BuildParams params;
};

pipeline::BuildParams toParams(const BuildOptions& o) {
  pipeline::BuildParams params = o.params;
  params.inputs.assign(o.inputs.begin(), o.inputs.end());
  if (o.trajectory) params.trajectory = *o.trajectory;
  if (o.origin) params.origin = mapper::parseVector3("--origin", *o.origin);
  params.frame = {mapper::parseUpAxis(o.up), o.scale};
  if (o.crop) params.filters.crop = mapper::parseBox("--crop", *o.crop);
  params.filters.z_min = o.z_min;
  params.filters.z_max = o.z_max;
  params.dbscan.metric = clustering::parseMetric(o.metric);
  return params;
}

/// Errors of the output directory named by the option that gave it.
template <typename F>
void naming(F&& write) {
  try {
    write();
  } catch (const Error& e) {
    throw Error("-o " + std::string(e.what()));
  }
}

/// Options that cannot apply to the run are refused, all named in one line: recording them as
/// applied would misstate the outputs. A finished octree is read as it is (no option that makes or
/// places one applies); a points-only build casts no rays (--max-range and --miss act on none).
bool readsOctree(const BuildOptions& options) {
  pipeline::BuildParams params;
  params.inputs.assign(options.inputs.begin(), options.inputs.end());
  return pipeline::readsOctree(params);
}

void refuseMisfits(const CLI::App& cmd, const BuildOptions& options) {
  if (!readsOctree(options)) {
    // Points alone are occupied updates only: nothing for a ray bound or P(miss) to act on.
    if (options.trajectory || options.origin || options.trajectory_topic) return;
    std::string given;
    for (const char* name : {"--max-range", "--miss"})
      if (cmd.count(name) > 0) given += (given.empty() ? "" : ", ") + std::string(name);
    if (given.empty()) return;
    throw Error(given + ": " + (given.find(',') == std::string::npos ? "applies" : "apply") +
                " only to free space cast along rays (with --trajectory or --origin); a points-only build casts "
                "none: leave " + (given.find(',') == std::string::npos ? "it" : "them") + " out");
  }
  std::string given;
  for (const char* name : {"--trajectory", "--origin", "--up", "--scale", "--crop", "--z-min", "--z-max",
                           "--resolution", "--max-range", "--hit", "--miss", "--clamp-min", "--clamp-max",
                           "--occupancy-threshold"}) {
    if (cmd.count(name) > 0) given += (given.empty() ? "" : ", ") + std::string(name);
  }
  if (given.empty()) return;
  throw Error(given + ": cannot apply to " + options.inputs.front() +
              ", a finished octree read as it is (its own frame, resolution and sensor model); leave " +
              (given.find(',') == std::string::npos ? "it" : "them") + " out, or build from the map points");
}

/// The output directory, checked before the work (pipeline::checkOutputDir) and named by -o; a
/// missing parent says that -p creates it.
void checkOutput(const BuildOptions& options, const pipeline::BuildParams& params) {
  try {
    pipeline::checkOutputDir(options.output_dir, params, {options.make_parents});
  } catch (const Error& e) {
    std::filesystem::path out = std::filesystem::absolute(options.output_dir).lexically_normal();
    if (out.filename().empty()) out = out.parent_path();
    std::error_code ec;
    const bool missing_parent = !options.make_parents && !std::filesystem::exists(out.parent_path(), ec);
    throw Error("-o " + std::string(e.what()) + (missing_parent ? " (give -p to create missing parents)" : ""));
  }
}

/// The last map on --topic of the one bag given, built as hullmap_node would build it.
pipeline::BuildResult buildFromBag(const BuildOptions& options, const pipeline::BuildParams& params) {
  if (options.inputs.size() != 1) throw Error("--topic: give exactly one input, a ROS1 bag");
  if (params.trajectory && options.trajectory_topic) throw Error("--trajectory and --trajectory-topic: give one or the other");
#ifdef HULLMAP_HAS_ROSBAG
  ros1::BagMap bag = ros1::readBagMap(options.inputs.front(), *options.topic);
  std::optional<std::vector<mapper::Keyframe>> keyframes;
  if (options.trajectory_topic) keyframes = ros1::readBagKeyframes(options.inputs.front(), *options.trajectory_topic);
  if (bag.skipped > 0) {
    std::cerr << "hullmap: warning: " << options.inputs.front() << ": " << bag.skipped << " malformed message"
              << (bag.skipped == 1 ? "" : "s") << " on " << *options.topic << " skipped\n";
  }
  if (bag.points.empty()) throw Error(options.inputs.front() + ": topic " + *options.topic + " ends on an empty map");
  return pipeline::buildFromPoints(std::move(bag.points), std::move(keyframes), params, options.inputs.front(),
                                   options.inputs.front() + ":" + options.trajectory_topic.value_or(""));
#else
  (void)params;
  throw Error("--topic: this hullmap was built without ROS1's rosbag_storage (install librosbag-storage-dev "
              "and pluginlib-dev, then rebuild)");
#endif
}

}  // namespace

void addBuildCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<BuildOptions>();
  auto* cmd = app.add_subcommand(
      "build", "Read SLAM dumps (or a .bt), build the octree, cluster it, wrap obstacles; write OUT/");
  cmd->add_option("inputs", options->inputs,
                  "Map-point files (ORB-SLAM echo dump, text/CSV, XYZ, PCD, PLY) unioned, or one .bt/.ot")
      ->required()
      ->check(existingFileOrStdin());
  cmd->add_option("-o,--output", options->output_dir,
                  "Output directory: new, empty, or a previous hullmap output (replaced whole on success); "
                  "any other directory is refused")
      ->capture_default_str();
  cmd->add_flag("-p,--parents", options->make_parents, "Create missing parent directories of -o (as mkdir -p)");
  cmd->add_option("--trajectory", options->trajectory,
                  "TUM keyframe trajectory: ray-cast free space from the keyframes")
      ->check(CLI::ExistingFile);
  cmd->add_option("--origin", options->origin,
                  "x,y,z (input frame): insert the points as one scan from this sensor origin");
  cmd->add_option("--up", options->up, "Input axis that points up: x, -x, y, -y, z, -z (ORB-SLAM: -y)")
      ->capture_default_str();
  cmd->add_option("--scale", options->scale, "Scale applied to input coordinates (monocular maps)")
      ->check(numberAbove(0))->capture_default_str();
  cmd->add_option("--crop", options->crop, "x0,y0,z0,x1,y1,z1: keep points inside this box (map frame)");
  cmd->add_option("--z-min", options->z_min, "Keep points with z >= this (map frame)")->check(finiteNumber());
  cmd->add_option("--z-max", options->z_max, "Keep points with z <= this (map frame)")->check(finiteNumber());
  auto& octree = options->params.octree;
  cmd->add_option("--resolution", octree.resolution, "Octree leaf size, map units")
      ->check(numberAbove(0))
      ->capture_default_str();
  cmd->add_option("--max-range", octree.max_range, "Bound on ray length for free space (< 0: none)")
      ->check(finiteNumber())->capture_default_str();
  cmd->add_option("--hit", octree.sensor.hit, "Sensor model: P(hit)")->check(numberIn(0.5, 1.0))
      ->capture_default_str();
  cmd->add_option("--miss", octree.sensor.miss, "Sensor model: P(miss)")->check(numberIn(0.0, 0.5))
      ->capture_default_str();
  cmd->add_option("--clamp-min", octree.sensor.clamp_min, "Lower clamping probability")
      ->check(numberIn(0.0, 1.0))->capture_default_str();
  cmd->add_option("--clamp-max", octree.sensor.clamp_max, "Upper clamping probability")
      ->check(numberIn(0.0, 1.0))->capture_default_str();
  cmd->add_option("--occupancy-threshold", octree.sensor.occupancy_threshold,
                  "Occupied when probability > this")
      ->check(numberIn(0.0, 1.0))->capture_default_str();
  cmd->add_option("--eps", options->params.dbscan.eps, "DBSCAN radius, map units (>= --resolution, or voxels stand alone)")
      ->check(numberAbove(0))->capture_default_str();
  cmd->add_option("--min-pts", options->params.dbscan.min_pts,
                  "DBSCAN core threshold, counted in map points (voxels weigh the points in them)")
      ->check(wholeNumberFrom(1))->capture_default_str();
  cmd->add_option("--metric", options->metric, "DBSCAN distance: xyz or xy (top view)")
      ->check(CLI::IsMember({"xyz", "xy"}))->capture_default_str();
  cmd->add_flag("--ot", options->params.write_ot, "Also write map.ot (full probabilities)");
  cmd->add_option("--topic", options->topic,
                  "The input is a ROS1 bag: build its last map on this topic (visualization_msgs/Marker as "
                  "/ORB_SLAM/Map, or sensor_msgs/PointCloud2), as hullmap_node would");
  cmd->add_option("--trajectory-topic", options->trajectory_topic,
                  "With --topic: keyframe poses from the bag (geometry_msgs/PoseStamped, one keyframe a message; or "
                  "nav_msgs/Path, the last message holding them all): ray-cast free space from them as --trajectory");

  cmd->callback([options, cmd, &status] {
    options->inputs = inputPaths(options->inputs);
    for (const auto& input : options->inputs) {
      if (!options->topic && input.size() > 4 && input.compare(input.size() - 4, 4, ".bag") == 0)
        throw Error(input + ": a ROS1 bag: give --topic, the map topic to read (as /ORB_SLAM/Map)");
    }
    refuseMisfits(*cmd, *options);
    const pipeline::BuildParams params = toParams(*options);
    const pipeline::WriteOptions write_options{options->make_parents};
    checkOutput(*options, params);
    if (options->trajectory_topic && !options->topic) throw Error("--trajectory-topic: needs --topic (a bag input)");
    pipeline::BuildResult result = options->topic ? buildFromBag(*options, params) : pipeline::build(params);
    std::vector<mapper::InputStats> named = result.report.inputs;
    if (options->trajectory) {
      named.emplace_back();
      named.back().path = *options->trajectory;  // KeyFrameTrajectory.txt names an ORB-SLAM run too
      named.back().format = "tum";
    }
    auto& warnings = result.report.warnings;
    if (auto hint = mapper::orbSlamUpHint(named, cmd->count("--up") > 0)) warnings.insert(warnings.begin(), *hint);
    for (const auto& warning : warnings) std::cerr << "hullmap: warning: " << warning << "\n";
    naming([&] { pipeline::write(result, options->output_dir, write_options); });
    const auto& a = result.report.points;
    std::cout << "points: " << a.read << " read, " << a.used << " used";
    for (const auto& [reason, count] : a.dropped) std::cout << ", " << count << " dropped (" << reason << ")";
    std::cout << "\noctree: " << result.voxels.size() << " occupied voxels at "
              << result.map.resolution() << "\nclusters: " << result.clusters.cluster_sizes.size()
              << ", noise voxels: " << result.clusters.noise
              << "\nobstacles: " << result.obstacles.size() << "\nwrote " << options->output_dir
              << "/{map.bt" << (options->params.write_ot ? ",map.ot" : "")
              << ",voxels.csv,obstacles.json,obstacles.obj,report.json}\n";
    status = 0;
  });
}

}  // namespace hullmap::cli
