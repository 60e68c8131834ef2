#include <iostream>
#include <memory>

#include "commands.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::cli {

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
  auto& octree = options->octree;
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
  cmd->add_option("--eps", options->dbscan.eps, "DBSCAN radius, map units")
      ->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--min-pts", options->dbscan.min_pts, "DBSCAN core threshold, in map points")
      ->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--metric", options->metric, "DBSCAN distance: xyz or xy (top view)")
      ->check(CLI::IsMember({"xyz", "xy"}))->capture_default_str();
  cmd->add_flag("--ot", options->write_ot, "Also write map.ot (full probabilities)");

  cmd->callback([options, &status] {
    checkOutputDir(options->output_dir);
    const BuildResult result = runBuild(*options);
    writeBuild(*options, result);
    const auto& a = result.account;
    std::cout << "points: " << a.read << " read, " << a.used << " used";
    for (const auto& [reason, count] : a.dropped) std::cout << ", " << count << " dropped (" << reason << ")";
    std::cout << "\noctree: " << result.voxels.size() << " occupied voxels at "
              << result.map->resolution() << "\nclusters: " << result.clusters.cluster_sizes.size()
              << ", noise voxels: " << result.clusters.noise
              << "\nobstacles: " << result.obstacles.size() << "\nwrote " << options->output_dir
              << "/{map.bt" << (options->write_ot ? ",map.ot" : "")
              << ",voxels.csv,obstacles.json,obstacles.obj,report.json}\n";
    status = 0;
  });
}

}  // namespace hullmap::cli
