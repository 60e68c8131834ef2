// Convex parts (hulls::addConvexParts) on a built map: its cost against the build's.
//
// usage: hullmap_bench_convex_parts MAP_POINTS [--up AXIS] [--eps E] [--min-pts N] [--trajectory TUM]
//                                   [--concavity T] [--repeat R] [--dump FILE]
//
// Builds the map as `hullmap build` would (pipeline::build with these parameters; keyframes from
// --trajectory are also given to addConvexParts in the map frame), then times addConvexParts on
// its obstacles, best of --repeat runs (wall clock). One JSON object on stdout:
//   {"voxels":..,"obstacles":..,"largest":..,"build_seconds":..,"parts_seconds":..,"parts":..,
//    "hull_volume_before":..,"hull_volume_after":..,"voxel_volume":..,"threads":..}
// --dump writes every part (obstacle id, voxels, volume, concavity bound, hull vertices) as text,
// so that two versions of the split can be compared byte for byte.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <tbb/info.h>

#include "hullmap/core/error.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/pipeline/pipeline.hpp"

int main(int argc, char** argv) try {
  if (argc < 2) {
    std::cerr << "usage: hullmap_bench_convex_parts MAP_POINTS [--up AXIS] [--eps E] [--min-pts N] "
                 "[--trajectory TUM] [--concavity T] [--repeat R] [--dump FILE]\n";
    return 2;
  }
  hullmap::pipeline::BuildParams params;
  params.inputs = {argv[1]};
  hullmap::hulls::ConvexPartsParams parts_params;
  int repeat = 1;
  std::string dump;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw hullmap::Error(arg + ": missing value");
      return argv[++i];
    };
    if (arg == "--up") {
      params.frame.up = hullmap::mapper::parseUpAxis(value());
    } else if (arg == "--eps") {
      params.eps = std::stod(value());
    } else if (arg == "--min-pts") {
      params.min_pts = std::stoi(value());
    } else if (arg == "--trajectory") {
      params.trajectory = value();
    } else if (arg == "--concavity") {
      parts_params.concavity = std::stod(value());
    } else if (arg == "--repeat") {
      repeat = std::max(1, std::stoi(value()));
    } else if (arg == "--dump") {
      dump = value();
    } else {
      std::cerr << "unknown argument " << arg << "\n";
      return 2;
    }
  }

  const auto b0 = std::chrono::steady_clock::now();
  const hullmap::pipeline::BuildResult built = hullmap::pipeline::build(params);
  const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - b0).count();
  std::vector<Eigen::Vector3d> centers;
  std::vector<std::uint32_t> weights;
  for (const auto& v : built.voxels) {
    centers.push_back(v.center);
    weights.push_back(v.weight);
  }
  hullmap::hulls::KnownFreeSpace known;
  if (params.trajectory) {
    std::vector<hullmap::io::Keyframe> keyframes = hullmap::io::readTumTrajectory(params.trajectory->string());
    hullmap::mapper::toMapFrame(params.frame, keyframes);
    for (const auto& k : keyframes) known.keyframes.push_back(k.position);
  }

  double best = 1e300;
  std::vector<hullmap::hulls::Obstacle> obstacles;
  hullmap::hulls::ConvexPartsSummary summary;
  for (int r = 0; r < repeat; ++r) {
    obstacles = built.obstacles;
    const auto t0 = std::chrono::steady_clock::now();
    summary = hullmap::hulls::addConvexParts(obstacles, centers, weights, built.clusters.labels, built.map.resolution(),
                                             parts_params, known);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::size_t largest = 0;
  for (const auto& o : obstacles) largest = std::max(largest, o.voxel_count);

  if (!dump.empty()) {
    std::ofstream out(dump);
    out.precision(17);
    for (const auto& o : obstacles)
      for (std::size_t p = 0; p < o.parts.size(); ++p) {
        const auto& part = o.parts[p];
        out << o.id << ' ' << p << ' ' << part.voxel_count << ' ' << part.volume << ' ' << part.concavity_bound << ' '
            << part.free_voxels_inside;
        for (const auto& v : part.hull.vertices) out << ' ' << v.x() << ' ' << v.y() << ' ' << v.z();
        out << '\n';
      }
  }
  std::printf(
      "{\"voxels\":%zu,\"obstacles\":%zu,\"largest\":%zu,\"build_seconds\":%.3f,\"parts_seconds\":%.3f,\"parts\":%zu,"
      "\"hull_volume_before\":%.4f,\"hull_volume_after\":%.4f,\"voxel_volume\":%.4f,\"keyframes_in_voxels\":%zu,"
      "\"threads\":%d}\n",
      centers.size(), obstacles.size(), largest, build_s, best, summary.parts, summary.hull_volume_before,
      summary.hull_volume_after, summary.voxel_volume, summary.keyframes_in_voxels, tbb::info::default_concurrency());
  return 0;
} catch (const std::exception& e) {
  std::cerr << "hullmap_bench_convex_parts: error: " << e.what() << "\n";
  return 2;
}
