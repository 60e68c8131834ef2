// Path checks: hull mode (HullChecker::checkBatch, the convex hulls of the clustered obstacles)
// against octree mode (OctreeChecker: FCL's OcTree collision and distance on every occupied voxel
// of the map), same segments, same radius, same machine, one run. Prints one JSON object per line:
//   {"scene": ..., "obstacles": K, "occupied_voxels": V, "radius": r, "segments": N, ...,
//    "hull_2t_per_s": .., "hull_1t_per_s": .., "octree_2t_per_s": .., "octree_1t_per_s": .., ...}
//
// Scenes go through `hullmap build`'s own pipeline (pipeline::build: frame, octree with keyframe ray
// casting, DBSCAN eps 0.1 minPts 10, CGAL hulls), at its defaults:
//   room           the sample map maps/simple (ROOM_DIR), read with --up -y and its trajectory;
//   generated_100  generateScene with 100 obstacles in a 30 m room (seed 42), written in ORB-SLAM's
//                  frame to a temporary directory and built the same way.
// Segments: uniform start in the room (z 0.2 .. room height - 0.2), uniform direction, length
// uniform in [0.5, 3] m, end inside the room; fixed seed. Radii 0.1 and 0.3 m.
//
// Timing: hull mode over --segments segments, octree mode over the first --octree-segments of them
// (it is orders of magnitude slower); median wall time of --repeat runs (octree: 1 run), on 2 threads
// (a two-thread task_arena; TBB over the segments: checkBatch for hull mode, the same parallel_for
// around check() for octree mode) and on 1 thread (a one-thread task_arena). CPU time (user + system
// of the process) of the same runs tells how much of the machine they had.
//
// FCL collide only: one fcl::collide of the segment's capsule against FCL's OcTree of the same map
// per segment, the bare yes/no (no first contact, no clearance), over the first --fcl-segments
// segments (median of 3 runs): the least FCL's octree collision costs for these segments, whatever a
// checker builds on it. `fcl_collide_disagree`: segments where it and octree mode differ (must be 0).
//
// Agreement, on the octree-mode segments: collide counts of both modes; `octree_only`: segments
// octree mode finds colliding and hull mode does not (the map's unclustered noise voxels and
// outliers), `hull_only` the reverse (hulls are convex and wrap their voxels completely). And octree
// mode once more on a tree holding only the clustered voxels: every hit there must be a hull hit no
// later than its first contact (`clustered_missed`, `clustered_later` must be 0).
//
// usage: hullmap_bench_collision ROOM_DIR [--segments N] [--octree-segments M] [--fcl-segments F]
//                                          [--repeat R]
#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/narrowphase/collision.h>
#include <octomap/OcTree.h>
#include <sys/resource.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/sample_scene.hpp"

namespace {

using hullmap::collision::HullChecker;
using hullmap::collision::OctreeChecker;
using hullmap::collision::Segment;
using hullmap::collision::SegmentCheck;
using V3 = Eigen::Vector3d;

double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  double one = 0, five = 0, fifteen = 0;
  in >> one >> five >> fifteen;
  char text[64];
  std::snprintf(text, sizeof text, "%.2f %.2f %.2f", one, five, fifteen);
  return text;
}

struct Timing {
  double wall = 0;  ///< seconds, median
  double cpu = 0;   ///< seconds, of the median run
};

/// Median wall time of `repeats` runs of `run`, with the CPU time of that run.
Timing timed(const std::function<void()>& run, int repeats) {
  std::vector<Timing> times;
  for (int r = 0; r < repeats; ++r) {
    const double c0 = cpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    run();
    const auto t1 = std::chrono::steady_clock::now();
    times.push_back({std::chrono::duration<double>(t1 - t0).count(), cpuSeconds() - c0});
  }
  std::sort(times.begin(), times.end(), [](const Timing& a, const Timing& b) { return a.wall < b.wall; });
  return times[times.size() / 2];
}

struct BuiltScene {
  std::string name;
  double room_size = 10;
  double room_height = 3;
  hullmap::pipeline::BuildResult build;
};

/// `hullmap build DIR/map_points.txt --trajectory DIR/KeyFrameTrajectory.txt --up -y`, defaults otherwise.
hullmap::pipeline::BuildResult buildLikeCli(const std::string& dir) {
  hullmap::pipeline::BuildParams params;
  params.inputs = {dir + "/map_points.txt"};
  params.trajectory = dir + "/KeyFrameTrajectory.txt";
  params.frame.up = hullmap::mapper::UpAxis::kNegY;
  return hullmap::pipeline::build(params);
}

std::vector<Segment> randomSegments(std::size_t n, double room_size, double room_height, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const V3 lo(-room_size / 2, -room_size / 2, 0.2), hi(room_size / 2, room_size / 2, room_height - 0.2);
  auto inside = [&](const V3& p) { return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all(); };
  std::vector<Segment> segments;
  segments.reserve(n);
  while (segments.size() < n) {
    const V3 a = lo + (hi - lo).cwiseProduct(V3(unit(rng), unit(rng), unit(rng)));
    V3 d;
    do {
      d = V3(2 * unit(rng) - 1, 2 * unit(rng) - 1, 2 * unit(rng) - 1);
    } while (d.squaredNorm() > 1 || d.squaredNorm() < 1e-6);
    const V3 b = a + d.normalized() * (0.5 + 2.5 * unit(rng));
    if (inside(b)) segments.push_back({a, b});
  }
  return segments;
}

/// The segment swept by a sphere of `radius`: an FCL capsule (as OctreeChecker builds it).
fcl::CollisionObjectd capsule(const Segment& segment, double radius) {
  const V3 d = segment.b - segment.a;
  const double length = d.norm();
  fcl::Transform3d pose = fcl::Transform3d::Identity();
  pose.translation() = segment.a + 0.5 * d;
  if (length > 0) pose.linear() = Eigen::Quaterniond::FromTwoVectors(V3::UnitZ(), d / length).toRotationMatrix();
  return fcl::CollisionObjectd(std::make_shared<fcl::Capsuled>(std::max(radius, 1e-9), length), pose);
}

/// Removes a directory when it goes out of scope.
struct TemporaryDirectory {
  std::filesystem::path path;
  ~TemporaryDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

/// How the checkers' answers agree: hits per checker, hits one has and the other not, the same
/// answers on one thread and two, and the clustered voxels' octree against the hulls.
struct Agreement {
  std::size_t hull_hits = 0, same_threads = 0;
  std::size_t hull_hits_m = 0, octree_hits = 0, octree_only = 0, hull_only = 0, clustered_hits = 0,
              clustered_missed = 0, clustered_later = 0, octree_same_threads = 0, fcl_disagree = 0;
};

Agreement agreement(const std::vector<SegmentCheck>& hull_results, const std::vector<SegmentCheck>& hull_results_1t,
                    const std::vector<SegmentCheck>& octree_results, const std::vector<SegmentCheck>& octree_results_1t,
                    const std::vector<SegmentCheck>& clustered_results, const std::vector<char>& fcl_hits,
                    const std::vector<Segment>& octree_segments) {
  Agreement a;
  for (std::size_t i = 0; i < hull_results.size(); ++i) {
    const SegmentCheck& x = hull_results[i];
    const SegmentCheck& y = hull_results_1t[i];
    a.hull_hits += x.collides;
    a.same_threads += x.collides == y.collides && x.obstacle == y.obstacle && x.t == y.t && x.clearance == y.clearance;
  }
  for (std::size_t i = 0; i < octree_segments.size(); ++i) {
    const SegmentCheck& h = hull_results[i];
    const SegmentCheck& o = octree_results[i];
    const SegmentCheck& c = clustered_results[i];
    a.hull_hits_m += h.collides;
    a.octree_hits += o.collides;
    a.octree_only += o.collides && !h.collides;
    a.hull_only += h.collides && !o.collides;
    a.octree_same_threads += o.collides == octree_results_1t[i].collides && o.t == octree_results_1t[i].t;
    if (i < fcl_hits.size()) a.fcl_disagree += bool(fcl_hits[i]) != o.collides;
    if (c.collides) {
      ++a.clustered_hits;
      const Segment& s = octree_segments[i];
      const double tolerance = std::max(1e-3, 1e-3 / (s.b - s.a).norm());
      a.clustered_missed += !h.collides;
      a.clustered_later += h.collides && h.t > c.t + tolerance;
    }
  }
  return a;
}

void run(const BuiltScene& scene, double radius, std::size_t n, std::size_t m, std::size_t f, int repeats) {
  const auto& obstacles = scene.build.obstacles;
  const octomap::OcTree& tree = scene.build.map.tree();
  const HullChecker hulls(obstacles);
  const OctreeChecker octree(tree);

  // The clustered voxels alone, as an octree (the agreement check's reference).
  octomap::OcTree clustered_tree(tree.getResolution());
  for (std::size_t i = 0; i < scene.build.voxels.size(); ++i) {
    if (scene.build.clusters.labels[i] < 0) continue;
    const V3& c = scene.build.voxels[i].center;
    clustered_tree.updateNode(octomap::point3d(float(c.x()), float(c.y()), float(c.z())), true);
  }
  const OctreeChecker clustered(clustered_tree);

  const std::vector<Segment> segments = randomSegments(n, scene.room_size, scene.room_height, 7);
  const std::vector<Segment> octree_segments(segments.begin(), segments.begin() + std::ptrdiff_t(std::min(n, m)));
  const std::vector<Segment> fcl_segments(segments.begin(), segments.begin() + std::ptrdiff_t(std::min(n, f)));

  tbb::task_arena one(1), two(2);
  std::vector<SegmentCheck> hull_results;
  const Timing hull_2t =
      timed([&] { two.execute([&] { hull_results = hulls.checkBatch(segments, radius); }); }, repeats);
  std::vector<SegmentCheck> hull_results_1t;
  const Timing hull_1t =
      timed([&] { one.execute([&] { hull_results_1t = hulls.checkBatch(segments, radius); }); }, repeats);

  auto octreeBatch = [&](const OctreeChecker& checker, std::vector<SegmentCheck>& out) {
    out.assign(octree_segments.size(), {});
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, octree_segments.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i)
                          out[i] = checker.check(octree_segments[i], radius);
                      });
  };
  std::vector<SegmentCheck> octree_results, octree_results_1t, clustered_results;
  const Timing octree_2t = timed([&] { two.execute([&] { octreeBatch(octree, octree_results); }); }, 1);
  const Timing octree_1t = timed([&] { one.execute([&] { octreeBatch(octree, octree_results_1t); }); }, 1);
  two.execute([&] { octreeBatch(clustered, clustered_results); });

  const auto fcl_tree = std::make_shared<const octomap::OcTree>(tree);
  fcl::CollisionObjectd fcl_map(std::make_shared<fcl::OcTreed>(fcl_tree));
  fcl_map.computeAABB();
  std::vector<char> fcl_hits;
  auto collideOnly = [&] {
    fcl_hits.assign(fcl_segments.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, fcl_segments.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          fcl::CollisionObjectd sweep = capsule(fcl_segments[i], radius);
                          fcl::CollisionRequestd request;
                          fcl::CollisionResultd answer;
                          fcl::collide(&sweep, &fcl_map, request, answer);
                          fcl_hits[i] = answer.isCollision();
                        }
                      });
  };
  const Timing fcl_2t = timed([&] { two.execute(collideOnly); }, 3);
  const Timing fcl_1t = timed([&] { one.execute(collideOnly); }, 3);

  const Agreement agree = agreement(hull_results, hull_results_1t, octree_results, octree_results_1t, clustered_results,
                                    fcl_hits, octree_segments);
  const double nd = double(n), md = double(octree_segments.size()), fd = double(fcl_segments.size());
  nlohmann::ordered_json row;
  row["scene"] = scene.name;
  row["obstacles"] = obstacles.size();
  row["occupied_voxels"] = scene.build.voxels.size();
  row["clustered_voxels"] = std::count_if(scene.build.clusters.labels.begin(), scene.build.clusters.labels.end(),
                                          [](std::int32_t label) { return label >= 0; });
  row["radius"] = radius;
  row["segments"] = n;
  row["octree_segments"] = octree_segments.size();
  row["fcl_segments"] = fcl_segments.size();
  auto timing = [&](const std::string& name, const Timing& t, double count) {
    row[name + "_s"] = t.wall;
    row[name + "_cpu_s"] = t.cpu;
    row[name + "_per_s"] = count / t.wall;
  };
  timing("hull_2t", hull_2t, nd);
  timing("hull_1t", hull_1t, nd);
  timing("octree_2t", octree_2t, md);
  timing("octree_1t", octree_1t, md);
  timing("fcl_collide_2t", fcl_2t, fd);
  timing("fcl_collide_1t", fcl_1t, fd);
  row["speedup_2t"] = (nd / hull_2t.wall) / (md / octree_2t.wall);
  row["speedup_1t"] = (nd / hull_1t.wall) / (md / octree_1t.wall);
  row["hull_hits"] = agree.hull_hits;
  row["hull_hit_fraction"] = double(agree.hull_hits) / nd;
  row["hull_hits_on_octree_segments"] = agree.hull_hits_m;
  row["octree_hits"] = agree.octree_hits;
  row["octree_only"] = agree.octree_only;
  row["hull_only"] = agree.hull_only;
  row["clustered_hits"] = agree.clustered_hits;
  row["clustered_missed"] = agree.clustered_missed;
  row["clustered_later"] = agree.clustered_later;
  row["fcl_collide_disagree"] = agree.fcl_disagree;
  row["threads_agree"] = agree.same_threads == n && agree.octree_same_threads == octree_segments.size();
  row["load_average"] = loadAverage();
  std::printf("%s\n", row.dump().c_str());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s ROOM_DIR [--segments N] [--octree-segments M] [--fcl-segments F] [--repeat R]\n",
                 argv[0]);
    return 2;
  }
  const std::string room_dir = argv[1];
  std::size_t n = 200000, m = 2000, f = 20000;
  int repeats = 5;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 >= argc) {
      std::fprintf(stderr, "%s: missing value\n", arg.c_str());
      return 2;
    }
    const std::string value = argv[++i];
    if (arg == "--segments") {
      n = std::max<std::size_t>(1, std::stoul(value));
    } else if (arg == "--octree-segments") {
      m = std::max<std::size_t>(1, std::stoul(value));
    } else if (arg == "--fcl-segments") {
      f = std::max<std::size_t>(1, std::stoul(value));
    } else if (arg == "--repeat") {
      repeats = std::max(1, std::stoi(value));
    } else {
      std::fprintf(stderr, "unknown argument %s\n", arg.c_str());
      return 2;
    }
  }

  try {
    std::vector<BuiltScene> scenes;
    scenes.push_back({"room", 10.0, 3.0, buildLikeCli(room_dir)});

    hullmap::sim::SceneParams params;
    params.seed = 42;
    params.obstacles = 100;
    params.room_size = 30.0;
    params.points = 500000;
    const TemporaryDirectory dir{std::filesystem::temp_directory_path() /
                                 ("hullmap_bench_collision." + std::to_string(::getpid()))};
    hullmap::sim::writeScene(hullmap::sim::generateScene(params), params, dir.path.string());
    scenes.push_back({"generated_100", params.room_size, params.room_height, buildLikeCli(dir.path.string())});

    for (const auto& scene : scenes)
      for (const double radius : {0.1, 0.3}) run(scene, radius, n, m, f, repeats);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hullmap_bench_collision: %s\n", e.what());
    return 1;
  }
  return 0;
}
