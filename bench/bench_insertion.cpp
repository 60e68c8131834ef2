// Scan insertion: hullmap's insertScan against octomap's insertPointCloud, same points, same
// origin, same machine, one run. Prints one JSON object per line:
//   {"scan": ..., "points": N, "resolution": r, "octomap_ms": ..., "hullmap_ms": ...,
//    "ray_keys_ms": ..., "cast_ms": ..., "apply_ms": ..., "leaves": L, "identical": true}
// octomap_ms: insertPointCloud into an empty tree. hullmap_ms: insertScan into an empty tree
// (clearing the previous tree, and trimming the heap after it, is not timed).
// ray_keys_ms: octomap's computeRayKeys for every point, nothing else (one thread: the floor of
// octomap's own approach). cast_ms / apply_ms: hullmap's two phases (parallel ray casting and
// deduplication; the ordered tree update). Medians of several runs.
//
// Scans: SCAN.dat; the generated room scene's points from its first keyframe (short rays, many
// through each voxel near the camera); a generated lidar scan of a large yard (long rays, few
// through each voxel). Each at 0.05, 0.1 and 0.2 m.
//
// usage: hullmap_bench_insertion SCAN.dat [repeats]   (SCAN: `x y z` text, sensor at the origin)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <octomap/OcTree.h>

#include "hullmap/core/constants.hpp"
#include "hullmap/core/random.hpp"
#include "hullmap/mapper/detail/octree_keys.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/sim/sample_scene.hpp"

namespace {

using hullmap::kPi;
using hullmap::io::Point;
using hullmap::io::Points;

// Median wall time of `run`; `setup` (not timed) runs before each repetition.
double millis(
    const std::function<void()>& run, int repeats, const std::function<void()>& setup = [] {}) {
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

// A spinning 64-beam lidar (elevations +2 to -24.9 degrees, as a Velodyne HDL-64E; 1024 steps of
// azimuth: 65,536 beams) 1.8 m above the ground of a 120 m x 90 m walled yard with buildings,
// parked cars and a row of poles: long rays spread over a large volume, as an outdoor scan.
// Metres, z up; every beam hits something; ranges carry +-2 cm of noise from a fixed hash (the same
// points on every machine with the same libm).
struct LidarScan {
  Points points;
  Point origin;
};

LidarScan lidarScan() {
  struct Box {
    Point lo, hi;
  };
  const std::vector<Box> boxes = {{{12, 8, 0}, {30, 22, 9}},        {{-35, 10, 0}, {-14, 28, 14}},
                                  {{-40, -30, 0}, {-22, -12, 6}},   {{18, -32, 0}, {40, -16, 11}},
                                  {{42, -5, 0}, {52, 12, 16}},      {{-55, -6, 0}, {-46, 6, 5}},
                                  {{4, -9.5, 0}, {8.5, -7.7, 1.5}}, {{-12, 4.2, 0}, {-7.5, 6, 1.5}},
                                  {{22, 3, 0}, {26.5, 4.8, 1.5}},   {{-20, -7.8, 0}, {-15.5, -6, 1.6}}};
  const double pole_radius = 0.15, pole_height = 6.0;
  const double yard[2] = {60.0, 45.0};
  const Point origin(0.0, 0.0, 1.8);

  LidarScan scan;
  scan.origin = origin;
  for (int beam = 0; beam < 64; ++beam) {
    const double elevation = (2.0 - 26.9 * beam / 63.0) * kPi / 180.0;
    for (int step = 0; step < 1024; ++step) {
      const double azimuth = 2.0 * kPi * step / 1024.0;
      const Point d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                    std::sin(elevation));
      // Walls (the ray leaves the yard) and ground.
      double t = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 2; ++a) {
        if (d[a] != 0.0) t = std::min(t, ((d[a] > 0 ? yard[a] : -yard[a]) - origin[a]) / d[a]);
      }
      if (d.z() < 0.0) t = std::min(t, -origin.z() / d.z());
      for (const Box& b : boxes) {
        double enter = 0.0, leave = t;
        for (int a = 0; a < 3; ++a) {
          if (d[a] == 0.0) {
            if (origin[a] < b.lo[a] || origin[a] > b.hi[a]) leave = -1.0;
            continue;
          }
          double t0 = (b.lo[a] - origin[a]) / d[a], t1 = (b.hi[a] - origin[a]) / d[a];
          if (t0 > t1) std::swap(t0, t1);
          enter = std::max(enter, t0);
          leave = std::min(leave, t1);
        }
        if (enter <= leave && enter > 0.0) t = enter;
      }
      // Poles along both sides of a street, every 10 m.
      for (int i = -5; i <= 5; ++i) {
        for (double side : {-5.5, 5.5}) {
          const double cx = 10.0 * i + 3.0, cy = side;
          const double ox = origin.x() - cx, oy = origin.y() - cy;
          const double qa = d.x() * d.x() + d.y() * d.y(), qb = ox * d.x() + oy * d.y();
          const double qc = ox * ox + oy * oy - pole_radius * pole_radius;
          const double disc = qb * qb - qa * qc;
          if (qa == 0.0 || disc < 0.0) continue;
          const double hit = (-qb - std::sqrt(disc)) / qa;
          if (hit > 0.0 && hit < t && origin.z() + hit * d.z() <= pole_height) t = hit;
        }
      }
      const std::uint64_t h =
          hullmap::core::splitMix64(static_cast<std::uint64_t>(beam) << 32 | static_cast<std::uint64_t>(step));
      const double noise = 0.02 * (2.0 * hullmap::core::unitInterval(h) - 1.0);
      scan.points.push_back(origin + (t + noise) * d);
    }
  }
  return scan;
}

// Empties the tree, and glibc's free lists with it: freeing millions of nodes leaves them in
// fastbins, and the next large allocation, whoever makes it, first consolidates them all (about a
// second after the 0.05 m lidar tree). Without this, that cost of the previous run's garbage
// lands in the timed insertion, octomap's and hullmap's alike.
void clearTree(octomap::OcTree& tree) {
  tree.clear();
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

bool identical(const octomap::OcTree& a, const octomap::OcTree& b) {
  if (a.size() != b.size()) return false;
  auto i = a.begin_leafs();
  auto j = b.begin_leafs();
  for (; i != a.end_leafs() && j != b.end_leafs(); ++i, ++j) {
    if (i.getKey() != j.getKey() || i.getDepth() != j.getDepth() ||
        std::abs(i->getLogOdds() - j->getLogOdds()) > 1e-5f) {
      return false;
    }
  }
  return i == a.end_leafs() && j == b.end_leafs();
}

void run(const std::string& name, const Points& points, const Point& origin, double resolution, int repeats) {
  octomap::Pointcloud cloud;
  for (const Point& p : points)
    cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  const octomap::point3d o(static_cast<float>(origin.x()), static_cast<float>(origin.y()),
                           static_cast<float>(origin.z()));

  octomap::OcTree reference(resolution);
  const double octomap_ms =
      millis([&] { reference.insertPointCloud(cloud, o, -1.0); }, repeats, [&] { clearTree(reference); });

  octomap::OcTree ours(resolution);
  const double hullmap_ms =
      millis([&] { hullmap::mapper::insertScan(ours, points, origin, -1.0); }, repeats, [&] { clearTree(ours); });

  std::size_t keys = 0;
  const double ray_keys_ms = millis(
      [&] {
        octomap::KeyRay ray;
        keys = 0;
        for (const auto& p : cloud) {
          if (reference.computeRayKeys(o, p, ray)) keys += ray.size();
        }
      },
      repeats);

  hullmap::mapper::detail::ScanUpdate update;
  const double cast_ms =
      millis([&] { update = hullmap::mapper::detail::computeScanUpdate(ours, points, origin, -1.0); }, repeats);
  octomap::OcTree phases(resolution);
  const double apply_ms =
      millis([&] { hullmap::mapper::detail::applyScanUpdate(phases, update); }, repeats, [&] { clearTree(phases); });

  std::printf(
      "{\"scan\": \"%s\", \"points\": %zu, \"resolution\": %.3f, \"octomap_ms\": %.2f, \"hullmap_ms\": %.2f, "
      "\"speedup\": %.2f, \"ray_keys_ms\": %.2f, \"cast_ms\": %.2f, \"apply_ms\": %.2f, \"ray_keys\": %zu, "
      "\"voxels_updated\": %zu, \"leaves\": %zu, \"identical\": %s}\n",
      name.c_str(), points.size(), resolution, octomap_ms, hullmap_ms, octomap_ms / hullmap_ms, ray_keys_ms, cast_ms,
      apply_ms, keys, update.voxelCount(), static_cast<std::size_t>(ours.getNumLeafNodes()),
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
  hullmap::sim::SceneParams params;
  params.points = 65536;
  params.gross_outliers = 0;
  params.orbslam_frame = false;
  const auto scene = hullmap::sim::generateScene(params);

  const LidarScan lidar = lidarScan();

  for (double resolution : {0.05, 0.1, 0.2}) {
    run("octomap_scan.dat", scan, Point::Zero(), resolution, repeats);
    run("generated_65536", scene.points, scene.keyframes.front().position, resolution, repeats);
    run("lidar_65536", lidar.points, lidar.origin, resolution, repeats);
  }
  return 0;
}
