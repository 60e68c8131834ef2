#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::cli {
namespace {

/// `hullmap build`'s options as typed; strings still to parse.
struct BuildOptions {
  std::vector<std::string> inputs;
  std::string output_dir = "out";
  std::optional<std::string> trajectory;
  std::optional<std::string> origin;  ///< "x,y,z"
  std::string up = "z";
  double scale = 1.0;
  std::optional<std::string> crop;    ///< "x0,y0,z0,x1,y1,z1"
  std::optional<double> z_min;
  std::optional<double> z_max;
  std::string metric = "xyz";
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

}  // namespace

void addBuildCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<BuildOptions>();
  auto* cmd = app.add_subcommand(
      "build", "Read SLAM dumps (or a .bt), build the octree, cluster it, wrap obstacles; write OUT/");
  cmd->add_option("inputs", options->inputs,
                  "Map-point files (ORB-SLAM echo dump, text/CSV, XYZ, PCD, PLY) unioned, or one .bt/.ot")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output_dir, "Output directory (replaced whole on success)")
      ->capture_default_str();
  cmd->add_option("--trajectory", options->trajectory,
                  "TUM keyframe trajectory: ray-cast free space from the keyframes")
      ->check(CLI::ExistingFile);
  cmd->add_option("--origin", options->origin,
                  "x,y,z (input frame): insert the points as one scan from this sensor origin");
  cmd->add_option("--up", options->up, "Input axis that points up: x, -x, y, -y, z, -z (ORB-SLAM: -y)")
      ->capture_default_str();
  cmd->add_option("--scale", options->scale, "Scale applied to input coordinates (monocular maps)")
      ->capture_default_str();
  cmd->add_option("--crop", options->crop, "x0,y0,z0,x1,y1,z1: keep points inside this box (map frame)");
  cmd->add_option("--z-min", options->z_min, "Keep points with z >= this (map frame)");
  cmd->add_option("--z-max", options->z_max, "Keep points with z <= this (map frame)");
  auto& octree = options->params.octree;
  cmd->add_option("--resolution", octree.resolution, "Octree leaf size, map units")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--max-range", octree.max_range, "Bound on ray length for free space (< 0: none)")
      ->capture_default_str();
  cmd->add_option("--hit", octree.sensor.hit, "Sensor model: P(hit)")->check(CLI::Range(0.5, 1.0))
      ->capture_default_str();
  cmd->add_option("--miss", octree.sensor.miss, "Sensor model: P(miss)")->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  cmd->add_option("--clamp-min", octree.sensor.clamp_min, "Lower clamping probability")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  cmd->add_option("--clamp-max", octree.sensor.clamp_max, "Upper clamping probability")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  cmd->add_option("--occupancy-threshold", octree.sensor.occupancy_threshold,
                  "Occupied when probability > this")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  cmd->add_option("--eps", options->params.dbscan.eps, "DBSCAN radius, map units")
      ->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--min-pts", options->params.dbscan.min_pts, "DBSCAN core threshold, in map points")
      ->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--metric", options->metric, "DBSCAN distance: xyz or xy (top view)")
      ->check(CLI::IsMember({"xyz", "xy"}))->capture_default_str();
  cmd->add_flag("--ot", options->params.write_ot, "Also write map.ot (full probabilities)");

  cmd->callback([options, &status] {
    naming([&] { pipeline::checkOutputDir(options->output_dir); });
    const pipeline::BuildResult result = pipeline::build(toParams(*options));
    naming([&] { pipeline::write(result, options->output_dir); });
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
