// Scan insertion: hullmap's insertScan against octomap's insertPointCloud, same points, same
// origin, same machine, one run. Prints one JSON object per line:
//   {"scan": ..., "points": N, "resolution": r, "octomap_ms": ..., "hullmap_ms": ...,
//    "ray_keys_ms": ..., "cast_ms": ..., "apply_ms": ..., "leaves": L, "identical": true}
// octomap_ms: insertPointCloud into an empty tree. hullmap_ms: insertScan into an empty tree
// (clearing the previous tree is not timed).
// ray_keys_ms: octomap's computeRayKeys for every point, nothing else (one thread: the floor of
// octomap's own approach). cast_ms / apply_ms: hullmap's two phases (parallel ray casting and
// deduplication; the ordered tree update). Medians of several runs.
//
// usage: hullmap_bench_insertion SCAN.dat [repeats]   (SCAN: `x y z` text, sensor at the origin)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <octomap/OcTree.h>

#include "../mapper/src/octree_keys.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/mapper/sample_scene.hpp"

namespace {

using hullmap::mapper::Point;
using hullmap::mapper::Points;

// Median wall time of `run`; `setup` (not timed) runs before each repetition.
double millis(const std::function<void()>& run, int repeats, const std::function<void()>& setup = [] {}) {
  std::vector<double> times;
  for (int r = 0; r < repeats; ++r) {
    setup();
    const auto start = std::chrono::steady_clock::now();
    run();
    times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

bool identical(const octomap::OcTree& a, const octomap::OcTree& b) {
  if (a.size() != b.size()) return false;
  auto i = a.begin_leafs();
  auto j = b.begin_leafs();
  for (; i != a.end_leafs() && j != b.end_leafs(); ++i, ++j) {
    if (i.getKey() != j.getKey() || i.getDepth() != j.getDepth() || std::abs(i->getLogOdds() - j->getLogOdds()) > 1e-5f) {
      return false;
    }
  }
  return i == a.end_leafs() && j == b.end_leafs();
}

void run(const std::string& name, const Points& points, const Point& origin, double resolution, int repeats) {
  octomap::Pointcloud cloud;
  for (const Point& p : points) cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  const octomap::point3d o(static_cast<float>(origin.x()), static_cast<float>(origin.y()), static_cast<float>(origin.z()));

  octomap::OcTree reference(resolution);
  const double octomap_ms = millis([&] { reference.insertPointCloud(cloud, o, -1.0); }, repeats,
                                   [&] { reference.clear(); });

  octomap::OcTree ours(resolution);
  const double hullmap_ms = millis([&] { hullmap::mapper::insertScan(ours, points, origin, -1.0); }, repeats,
                                   [&] { ours.clear(); });

  std::size_t keys = 0;
  const double ray_keys_ms = millis([&] {
    octomap::KeyRay ray;
    keys = 0;
    for (const auto& p : cloud) {
      if (reference.computeRayKeys(o, p, ray)) keys += ray.size();
    }
  }, repeats);

  std::vector<hullmap::mapper::detail::VoxelUpdate> updates;
  const double cast_ms = millis([&] {
    updates = hullmap::mapper::detail::computeScanUpdate(ours, points, origin, -1.0);
  }, repeats);
  octomap::OcTree phases(resolution);
  std::vector<hullmap::mapper::detail::VoxelUpdate> copy;
  const double apply_ms = millis([&] { hullmap::mapper::detail::applyUpdates(phases, copy); }, repeats, [&] {
    phases.clear();
    copy = updates;
  });

  std::printf(
      "{\"scan\": \"%s\", \"points\": %zu, \"resolution\": %.3f, \"octomap_ms\": %.2f, \"hullmap_ms\": %.2f, "
      "\"speedup\": %.2f, \"ray_keys_ms\": %.2f, \"cast_ms\": %.2f, \"apply_ms\": %.2f, \"ray_keys\": %zu, "
      "\"voxels_updated\": %zu, \"leaves\": %zu, \"identical\": %s}\n",
      name.c_str(), points.size(), resolution, octomap_ms, hullmap_ms, octomap_ms / hullmap_ms, ray_keys_ms, cast_ms,
      apply_ms, keys, updates.size(), static_cast<std::size_t>(ours.getNumLeafNodes()),
      identical(reference, ours) && identical(reference, phases) ? "true" : "false");
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCAN.dat [repeats]\n", argv[0]);
    return 2;
  }
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  Points scan;
  {
    std::ifstream in(argv[1]);
    double x, y, z;
    while (in >> x >> y >> z) scan.emplace_back(x, y, z);
    if (scan.empty()) {
      std::fprintf(stderr, "%s: no points read\n", argv[1]);
      return 2;
    }
  }
  hullmap::mapper::SceneParams params;
  params.points = 65536;
  params.gross_outliers = 0;
  params.orbslam_frame = false;
  const auto scene = hullmap::mapper::generateScene(params);

  for (double resolution : {0.05, 0.1, 0.2}) {
    run("octomap_scan.dat", scan, Point::Zero(), resolution, repeats);
    run("generated_65536", scene.points, scene.keyframes.front().position, resolution, repeats);
  }
  return 0;
}
