#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "build_summary.hpp"
#include "cli_main.hpp"
#include "commands.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/live/ros2_bag.hpp"
#include "hullmap/mapper/level_check.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "option_checks.hpp"

namespace hullmap::cli {

Ros1BagReader ros1_bag_reader = nullptr;

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
  std::optional<std::string> crop;  ///< "x0,y0,z0,x1,y1,z1"
  std::optional<double> z_min;
  std::optional<double> z_max;
  std::string metric = "xyz";
  std::optional<std::string> topic;             ///< the input is a ROS 1 or ROS 2 bag: its map topic
  std::optional<std::string> trajectory_topic;  ///< and its keyframe poses' topic
  std::optional<std::string> align;             ///< reference trajectory
  std::string align_format = "tum";
  double align_tolerance = mapper::AlignParams{}.stamp_tolerance;
  std::string align_model = "auto";
  std::string floor = "auto";
  std::string level = "auto";
  std::string ceiling = "none";
  std::string eps = "auto";
  std::string min_pts = "auto";
  std::string concavity = "default";
  std::string flat_gap = "auto";    ///< G of flat parts: auto (the eps used), 0 (off) or a length
  std::string extension = "auto";   ///< auto (on when --min-pts is auto), on or off
  std::string sparse_edges = "on";  ///< --sparse-edges: on or off
  std::size_t stray_parts = 3;      ///< --stray-parts: the largest stray part dropped, in voxels (0: none)
  pipeline::BuildParams params;
};

double number(const std::string& text) { return std::stod(text); }  // validated by the option's check

pipeline::BuildParams toParams(const BuildOptions& o) {
  pipeline::BuildParams params = o.params;
  params.inputs.assign(o.inputs.begin(), o.inputs.end());
  if (o.trajectory) params.trajectory = *o.trajectory;
  if (o.origin) params.origin = mapper::parseVector3("--origin", *o.origin);
  params.frame = {mapper::parseUpAxis(o.up), o.scale};
  if (o.crop) params.filters.crop = mapper::parseBox("--crop", *o.crop);
  params.filters.z_min = o.z_min;
  params.filters.z_max = o.z_max;
  params.metric = clustering::parseMetric(o.metric);
  if (o.align) {
    pipeline::AlignSettings align;
    align.reference = *o.align;
    align.format = io::parseReferenceFormat(o.align_format);
    align.params.stamp_tolerance = o.align_tolerance;
    align.params.model = mapper::parseAlignModel(o.align_model);
    params.align = align;
  }
  params.floor = mapper::parsePlaneSetting("--floor", o.floor);
  params.level = o.level == "on"    ? pipeline::Level::kOn
                 : o.level == "off" ? pipeline::Level::kOff
                                    : pipeline::Level::kAuto;
  params.ceiling = mapper::parsePlaneSetting("--ceiling", o.ceiling);
  if (o.eps != "auto") params.eps = number(o.eps);
  if (o.min_pts != "auto") params.min_pts = std::stoi(o.min_pts);
  if (o.concavity == "none") {
    params.convex_parts.reset();
  } else if (o.concavity != "default") {
    params.convex_parts->concavity = number(o.concavity);
  }
  if (params.convex_parts && o.flat_gap != "auto") params.convex_parts->flat_gap = number(o.flat_gap);
  if (o.extension != "auto") params.extension = o.extension == "on";
  params.stray_part_voxels = o.stray_parts;
  params.sparse_edges = o.sparse_edges == "on";
  return params;
}

/// An input: a file, - (standard input), or a ROS 2 bag's directory (with --topic).
CLI::Validator inputFileOrBag() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::error_code ec;
        if (text != "-" && std::filesystem::is_directory(text, ec) && live::isRos2Bag(text)) return "";
        return existingFileOrStdin()(text);
      },
      "FILE, BAG or -");
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
  if (options.align && !options.trajectory)
    throw Error("--align: needs --trajectory (the keyframes fitted to the reference trajectory)");
  if (options.align) {
    for (const char* name : {"--up", "--scale"})
      if (cmd.count(name) > 0)
        throw Error(std::string(name) +
                    ": cannot apply with --align (the reference trajectory sets the frame and scale); leave it out");
  } else {
    for (const char* name : {"--align-format", "--align-tolerance", "--align-model"})
      if (cmd.count(name) > 0) throw Error(std::string(name) + ": applies only with --align REF");
  }
  if (options.concavity == "none" && cmd.count("--flat-gap") > 0)
    throw Error(
        "--flat-gap: applies only to convex parts, and --concavity none makes one hull per cluster; "
        "leave it out");
  if (!readsOctree(options)) {
    // Points alone are occupied updates only: nothing for a ray bound or P(miss) to act on.
    if (options.trajectory || options.origin || options.trajectory_topic) return;
    std::string given;
    for (const char* name : {"--max-range", "--miss"})
      if (cmd.count(name) > 0) given += (given.empty() ? "" : ", ") + std::string(name);
    if (given.empty()) return;
    throw Error(given + ": " + (given.find(',') == std::string::npos ? "applies" : "apply") +
                " only to free space cast along rays (with --trajectory or --origin); a points-only build casts "
                "none: leave " +
                (given.find(',') == std::string::npos ? "it" : "them") + " out");
  }
  std::string given;
  for (const char* name : {"--trajectory", "--origin", "--up", "--scale", "--crop", "--z-min", "--z-max",
                           "--resolution", "--max-range", "--hit", "--miss", "--clamp-min", "--clamp-max",
                           "--occupancy-threshold", "--align", "--floor", "--level", "--ceiling"}) {
    if (cmd.count(name) > 0) given += (given.empty() ? "" : ", ") + std::string(name);
  }
  if (given.empty()) return;
  throw Error(given + ": cannot apply to " + options.inputs.front() +
              ", a finished octree read as it is (its own frame, resolution and sensor model); leave " +
              (given.find(',') == std::string::npos ? "it" : "them") + " out, or build from the map points");
}

/// The output directory, checked before the work (pipeline::checkOutputDir with the build's outputPolicy) and named by
/// -o; a missing parent says that -p creates it.
void checkOutput(const BuildOptions& options, const pipeline::BuildParams& params) {
  try {
    pipeline::checkOutputDir(options.output_dir, pipeline::outputPolicy(params, {options.make_parents}));
  } catch (const Error& e) {
    std::filesystem::path out = std::filesystem::absolute(options.output_dir).lexically_normal();
    if (out.filename().empty()) out = out.parent_path();
    std::error_code ec;
    const bool missing_parent = !options.make_parents && !std::filesystem::exists(out.parent_path(), ec);
    throw Error("-o " + std::string(e.what()) + (missing_parent ? " (give -p to create missing parents)" : ""));
  }
}

/// The last map on --topic of the one bag given, built as hullmap_node would build it: a ROS 2 bag
/// (a directory with metadata.yaml, a .db3 or .mcap file) read by rosbag2 through hullmap_ros2's
/// reader, a ROS 1 bag by Debian's rosbag_storage.
pipeline::BuildResult buildFromBag(const BuildOptions& options, const pipeline::BuildParams& params) {
  if (options.inputs.size() != 1) throw Error("--topic: give exactly one input, a ROS 1 or ROS 2 bag");
  if (params.trajectory && options.trajectory_topic)
    throw Error("--trajectory and --trajectory-topic: give one or the other");
  const std::string& path = options.inputs.front();
  live::BagTopics bag;
  if (live::isRos2Bag(path)) {
    bag = live::readRos2Bag(path, *options.topic, options.trajectory_topic);
  } else {
    if (ros1_bag_reader == nullptr)
      throw Error(
          "--topic: this hullmap was built without ROS1's rosbag_storage (install librosbag-storage-dev "
          "and pluginlib-dev, then rebuild)");
    bag = ros1_bag_reader(path, *options.topic, options.trajectory_topic);
  }
  if (bag.map.skipped > 0) {
    std::cerr << "hullmap: warning: " << path << ": " << bag.map.skipped << " malformed message"
              << (bag.map.skipped == 1 ? "" : "s") << " on " << *options.topic << " skipped\n";
  }
  if (bag.map.points.empty()) throw Error(path + ": topic " + *options.topic + " ends on an empty map");
  // ORB-SLAM's map markers are in its first camera's frame; a PointCloud2 is judged as a file is.
  pipeline::BuildParams bag_params = params;
  if (!bag_params.camera_frame &&
      (bag.map.type == "visualization_msgs/Marker" || bag.map.type == "visualization_msgs/msg/Marker"))
    bag_params.camera_frame = true;
  return pipeline::buildFromPoints(std::move(bag.map.points), std::move(bag.keyframes), bag_params, path,
                                   path + ":" + options.trajectory_topic.value_or(""));
}

// The inputs, the output directory, and the input frame: keyframes, sensor origin, up, scale, crop.
void addInputOptions(CLI::App& cmd, BuildOptions& options) {
  cmd.add_option("inputs", options.inputs,
                 "Map-point files (ORB-SLAM echo dump, text/CSV, XYZ, PCD, PLY) unioned, or one .bt/.ot, or one "
                 "ROS 1 or ROS 2 bag with --topic")
      ->required()
      ->check(inputFileOrBag());
  cmd.add_option("-o,--output", options.output_dir,
                 "Output directory: new, empty, or a previous hullmap output (replaced whole on success); "
                 "any other directory is refused")
      ->capture_default_str();
  cmd.add_flag("-p,--parents", options.make_parents, "Create missing parent directories of -o (as mkdir -p)");
  cmd.add_option("--trajectory", options.trajectory, "TUM keyframe trajectory: ray-cast free space from the keyframes")
      ->check(CLI::ExistingFile);
  cmd.add_option("--origin", options.origin,
                 "x,y,z (input frame): insert the points as one scan from this sensor origin");
  cmd.add_option("--up", options.up, "Input axis that points up: x, -x, y, -y, z, -z (ORB-SLAM: -y)")
      ->capture_default_str();
  cmd.add_option("--scale", options.scale, "Scale applied to input coordinates (monocular maps)")
      ->check(numberAbove(0))
      ->capture_default_str();
  cmd.add_option("--crop", options.crop,
                 "x0,y0,z0,x1,y1,z1: keep points inside this box (output frame: after --up/--scale or --align and "
                 "levelling; the input frame when none moved the map)");
  cmd.add_option("--z-min", options.z_min, "Keep points with z >= this (output frame, as --crop)")
      ->check(finiteNumber());
  cmd.add_option("--z-max", options.z_max, "Keep points with z <= this (output frame, as --crop)")
      ->check(finiteNumber());
}

// The octree: its resolution, ray length and sensor model.
void addOctreeOptions(CLI::App& cmd, BuildOptions& options) {
  auto& octree = options.params.octree;
  cmd.add_option("--resolution", octree.resolution, "Octree leaf size, map units")
      ->check(numberAbove(0))
      ->capture_default_str();
  cmd.add_option("--max-range", octree.max_range, "Bound on ray length for free space (< 0: none)")
      ->check(finiteNumber())
      ->capture_default_str();
  cmd.add_option("--hit", octree.sensor.hit, "Sensor model: P(hit)")->check(numberIn(0.5, 1.0))->capture_default_str();
  cmd.add_option("--miss", octree.sensor.miss, "Sensor model: P(miss)")
      ->check(numberIn(0.0, 0.5))
      ->capture_default_str();
  cmd.add_option("--clamp-min", octree.sensor.clamp_min, "Lower clamping probability")
      ->check(numberIn(0.0, 1.0))
      ->capture_default_str();
  cmd.add_option("--clamp-max", octree.sensor.clamp_max, "Upper clamping probability")
      ->check(numberIn(0.0, 1.0))
      ->capture_default_str();
  cmd.add_option("--occupancy-threshold", octree.sensor.occupancy_threshold, "Occupied when probability > this")
      ->check(numberIn(0.0, 1.0))
      ->capture_default_str();
}

// --align: a metric reference trajectory and how to read and match it.
void addAlignOptions(CLI::App& cmd, BuildOptions& options) {
  cmd.add_option(
         "--align", options.align,
         "Metric reference trajectory of the keyframes (needs --trajectory): outputs in its frame, metres, z up")
      ->check(CLI::ExistingFile);
  cmd.add_option("--align-format", options.align_format, "Format of --align: tum (t x y z [q]) or gps (t lat lon alt)")
      ->check(CLI::IsMember({"tum", "gps"}))
      ->capture_default_str();
  cmd.add_option("--align-tolerance", options.align_tolerance,
                 "Seconds within which a keyframe matches a reference stamp")
      ->check(numberAbove(0, true))
      ->capture_default_str();
  cmd.add_option("--align-model", options.align_model,
                 "How the map follows the reference: similarity (one for the whole map), drift (scale and "
                 "translation along the path: monocular scale drift) or auto (drift when it fits far better)")
      ->check(CLI::IsMember({"auto", "similarity", "drift"}))
      ->capture_default_str();
}

// Floor, levelling and ceiling.
void addSurfaceOptions(CLI::App& cmd, BuildOptions& options) {
  cmd.add_option("--floor", options.floor,
                 "auto: find the floor, none, or its height Z; floor voxels are not clustered, and the floor is an "
                 "obstacle for check and plan")
      ->check(wordOr({"auto", "none"}, finiteNumber()))
      ->capture_default_str();
  cmd.add_option("--level", options.level,
                 "auto: level a found floor (rotate it level, move it to z = 0) only for a camera's frame (ORB-SLAM "
                 "maps, --up other than z); on: always; off: never (the map stays in its input frame)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  cmd.add_option("--ceiling", options.ceiling, "auto, none, or its height Z: ceiling voxels are not clustered")
      ->check(wordOr({"auto", "none"}, finiteNumber()))
      ->capture_default_str();
}

// DBSCAN, its automatic parameters and extension, and the convex parts.
void addClusterOptions(CLI::App& cmd, BuildOptions& options) {
  cmd.add_option("--eps", options.eps, "DBSCAN radius, map units (>= --resolution), or auto: chosen from the map")
      ->check(wordOr({"auto"}, numberAbove(0)))
      ->capture_default_str();
  cmd.add_option("--min-pts", options.min_pts,
                 "DBSCAN core threshold, counted in map points (voxels weigh the points in them), or auto")
      ->check(wordOr({"auto"}, wholeNumberFrom(1)))
      ->capture_default_str();
  cmd.add_option("--concavity", options.concavity,
                 "Split clusters into convex parts no farther than T (map units) from their voxels; "
                 "default: 3 voxels; none: one hull per cluster")
      ->check(wordOr({"default", "none"}, numberAbove(0)))
      ->capture_default_str();
  cmd.add_option("--flat-gap", options.flat_gap,
                 "Convex parts at most T thick (walls, table tops) may span gaps up to G (map units) instead "
                 "of T; auto: the eps used, raised on sparse clusters to the holes their sampling leaves by chance "
                 "(at most 2 eps); 0: off")
      ->check(wordOr({"auto"}, numberAbove(0, true)))
      ->capture_default_str();
  cmd.add_option("--extension", options.extension,
                 "After DBSCAN, noise voxels dense at a lower level (min-pts x 0.3, at least 2) join the cluster "
                 "a chain of them reaches within 1.5 eps (sparse legs and edges); auto: on when --min-pts is auto")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  cmd.add_option("--sparse-edges", options.sparse_edges,
                 "Grow each sparse convex part in its own plane by a share of its point spacing (1.5 x the spacing "
                 "beyond 2.4 voxels, at most 2 voxels), to the edges and corners its last map points stop short of")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  cmd.add_option(
         "--stray-parts", options.stray_parts,
         "With the extension: drop a convex part of at most N voxels, at most one of them core, of an obstacle "
         "with other parts and farther than 2 T from the floor, ceiling and ground (stray map points a wide eps "
         "took in off a surface); 0: keep every part")
      ->check(wholeNumberFrom(0))
      ->capture_default_str();
  cmd.add_option("--metric", options.metric, "DBSCAN distance: xyz or xy (top view)")
      ->check(CLI::IsMember({"xyz", "xy"}))
      ->capture_default_str();
}

// map.ot, and bag inputs (--topic, --trajectory-topic).
void addBagOptions(CLI::App& cmd, BuildOptions& options) {
  cmd.add_flag("--ot", options.params.write_ot, "Also write map.ot (full probabilities)");
  cmd.add_option("--topic", options.topic,
                 "The input is a ROS 1 bag (.bag) or a ROS 2 bag (its directory, .db3 or .mcap; read through the "
                 "ROS 2 package hullmap_ros2): build its last map on this topic (visualization_msgs/Marker as "
                 "/ORB_SLAM/Map, or sensor_msgs/PointCloud2), as hullmap_node would");
  cmd.add_option("--trajectory-topic", options.trajectory_topic,
                 "With --topic: keyframe poses from the bag (geometry_msgs/PoseStamped, one keyframe a message; or "
                 "nav_msgs/Path, the last message holding them all): ray-cast free space from them as --trajectory");
}

// The build a parsed command line asks for: read, build, write, print what was done.
void runBuild(BuildOptions& options, const CLI::App& cmd) {
  options.inputs = inputPaths(options.inputs);
  for (const auto& input : options.inputs) {
    if (!options.topic && input.size() > 4 && input.compare(input.size() - 4, 4, ".bag") == 0)
      throw Error(input + ": a ROS1 bag: give --topic, the map topic to read (as /ORB_SLAM/Map)");
    if (!options.topic && live::isRos2Bag(input))
      throw Error(input + ": a ROS 2 bag: give --topic, the map topic to read (as /ORB_SLAM/Map)");
  }
  refuseMisfits(cmd, options);
  const pipeline::BuildParams params = toParams(options);
  const pipeline::WriteOptions write_options{options.make_parents, optionSpelling};
  checkOutput(options, params);
  if (options.trajectory_topic && !options.topic) throw Error("--trajectory-topic: needs --topic (a bag input)");
  pipeline::BuildResult result = options.topic ? buildFromBag(options, params) : pipeline::build(params);
  std::vector<io::InputStats> named = result.report.inputs;
  if (options.trajectory) {
    named.emplace_back();
    named.back().path = *options.trajectory;  // KeyFrameTrajectory.txt names an ORB-SLAM run too
    named.back().format = "tum";
  }
  auto& warnings = result.report.warnings;
  if (auto hint = mapper::orbSlamUpHint(named, cmd.count("--up") > 0 || options.align.has_value()))
    warnings.insert(warnings.begin(), *hint);
  for (const auto& warning : warnings)
    std::cerr << "hullmap: warning: " << warningText(warning, optionSpelling) << "\n";
  naming([&] { pipeline::write(result, options.output_dir, write_options); });
  const auto& a = result.report.points;
  std::cout << "points: " << a.read << " read, " << a.used << " used";
  for (const auto& [reason, count] : a.dropped) std::cout << ", " << count << " dropped (" << reason << ")";
  std::cout << "\n";
  printStages(result);
  std::cout << "octree: " << result.voxels.size() << " occupied voxels at " << result.map.resolution()
            << "\nclusters: " << result.clusters.cluster_sizes.size() << ", noise voxels: " << result.clusters.noise
            << "\n";
  printClustering(result);
  std::cout << "wrote " << options.output_dir << "/{map.bt" << (options.params.write_ot ? ",map.ot" : "")
            << ",voxels.csv,obstacles.json,obstacles.obj,report.json"
            << (result.keyframes.empty() ? "" : ",trajectory.txt") << "}\n";
}

}  // namespace

void addBuildCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<BuildOptions>();
  auto* cmd = app.add_subcommand(
      "build", "Read SLAM dumps (or a .bt), build the octree, cluster it, wrap obstacles; write OUT/");
  addInputOptions(*cmd, *options);
  addOctreeOptions(*cmd, *options);
  addAlignOptions(*cmd, *options);
  addSurfaceOptions(*cmd, *options);
  addClusterOptions(*cmd, *options);
  addBagOptions(*cmd, *options);
  cmd->callback([options, cmd, &status] {
    // A resolution given is the octree's; the default adapts to a sparse map.
    options->params.adapt_resolution = cmd->count("--resolution") == 0;
    runBuild(*options, *cmd);
    status = 0;
  });
}

}  // namespace hullmap::cli
