// Issue 27: on cluttered generated rooms (8 x 6 x 3 m, 9-16 pieces of furniture standing free, sparse
// like EuRoC V1_01, ORB-SLAM's frame at a monocular scale), built at the defaults with --trajectory
// --align, the walls' parts stay on the walls: no hull of a part whose voxels came from a wall reaches
// farther than the concavity T plus one voxel from the true surfaces its voxels came from.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/evaluate.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace {

using V3 = Eigen::Vector3d;
namespace pipeline = hullmap::pipeline;
namespace mapper = hullmap::mapper;
namespace clustering = hullmap::clustering;

struct RoomCase {
  std::uint64_t seed;
  double pitch;    ///< degrees
  double scale;    ///< monocular scale, map units per metre
  double density;  ///< map points per m^2 of visible surface
  std::size_t furniture;
};

std::string caseName(const RoomCase& c) {
  std::ostringstream s;
  s << "s" << c.seed << "-p" << c.pitch << "-x" << c.scale << "-d" << c.density << "-f" << c.furniture;
  return s.str();
}

/// The room: 8 x 6 x 3 m, the camera loop a quarter of the way in, the furniture anywhere
/// off the loop, a share `wall_fraction` of it against the walls (0: 0.5 m from them, the walls' own
/// cluster), ORB-SLAM's frame; as bench/quality.py's sweep writes it.
pipeline::BuildResult buildRoom(const RoomCase& c, std::filesystem::path& dir, double wall_fraction = 0.0) {
  hullmap::sim::SceneParams p;
  p.layout = hullmap::sim::SceneLayout::kRoom;
  p.seed = c.seed;
  p.room_size = 8.0;
  p.room_width = 6.0;
  p.loop_fraction = 0.25;
  p.placement = hullmap::sim::FurniturePlacement::kAnywhere;
  p.wall_fraction = wall_fraction;
  p.obstacles = c.furniture;
  p.density = c.density;
  p.camera_pitch_deg = c.pitch;
  p.monocular_scale = c.scale;
  const hullmap::sim::Scene scene = hullmap::sim::generateScene(p);
  dir = hullmap::test::freshDir(caseName(c));
  hullmap::sim::writeScene(scene, p, dir.string());
  pipeline::BuildParams build;
  build.inputs = {dir / "map_points.txt"};
  build.trajectory = dir / "KeyFrameTrajectory.txt";
  build.align = pipeline::AlignSettings{dir / "reference_trajectory.txt", {}, {}};
  return pipeline::build(build);
}

/// The truth's primitives (a union's parts each), with the object each belongs to.
struct Primitive {
  const hullmap::sim::TruthShape* shape;
  std::size_t object;
};

std::vector<Primitive> primitives(const hullmap::sim::GroundTruth& truth) {
  std::vector<Primitive> out;
  for (std::size_t s = 0; s < truth.shapes.size(); ++s)
    for (const auto& part : truth.shapes[s].primitives()) out.push_back({&part, s});
  return out;
}

/// One part, and how far its hull reaches from the true surfaces its voxels came from.
struct PartReach {
  int obstacle = 0;
  std::size_t part = 0;
  std::size_t voxels = 0;
  std::size_t off_surface = 0;       ///< voxels that came from no surface (farther than the noise margin)
  std::vector<std::size_t> sources;  ///< primitives the other voxels came from
  double reach = 0.0;                ///< largest distance from them of a hull point outside the truth
  V3 where = V3::Zero();
  bool flat = false, faces = false, filled = false;
};

/// Points of a hull at which its distance from convex primitives peaks: its vertices (the distance
/// to a convex set is convex); with several primitives (their union's distance may peak inside), also
/// the points of a grid of `step` over its box that lie in it.
std::vector<V3> hullSamples(const hullmap::hulls::ConvexHull& hull, const V3& lo, const V3& hi, bool grid,
                            double step) {
  std::vector<V3> out = hull.vertices;
  if (!grid) return out;
  std::vector<std::pair<V3, double>> planes;
  for (const auto& t : hull.triangles) {
    const V3& a = hull.vertices[std::size_t(t[0])];
    V3 n = (hull.vertices[std::size_t(t[1])] - a).cross(hull.vertices[std::size_t(t[2])] - a);
    if (n.norm() == 0) continue;
    n.normalize();
    planes.emplace_back(n, n.dot(a));
  }
  for (double x = lo.x(); x <= hi.x(); x += step)
    for (double y = lo.y(); y <= hi.y(); y += step)
      for (double z = lo.z(); z <= hi.z(); z += step) {
        const V3 p(x, y, z);
        if (std::all_of(planes.begin(), planes.end(),
                        [&](const auto& pl) { return pl.first.dot(p) <= pl.second + 1e-9; }))
          out.push_back(p);
      }
  return out;
}

/// Every part of the build with its reach. A voxel came from the primitive nearest its centre when
/// that is within `noise_margin`, else from none (an outlier). The parts' voxels are split again with
/// the build's own parameters (splitConvexParts gives the parts addConvexParts wraps; the stray parts
/// it dropped are left out again).
std::vector<PartReach> partReaches(const pipeline::BuildResult& r, const hullmap::sim::GroundTruth& truth,
                                   double noise_margin) {
  const double res = r.map.resolution();
  const std::vector<Primitive> prims = primitives(truth);
  std::vector<int> source(r.voxels.size(), -1);
  for (std::size_t i = 0; i < r.voxels.size(); ++i) {
    if (r.clusters.labels[i] < 0) continue;
    double best = noise_margin;
    for (std::size_t k = 0; k < prims.size(); ++k) {
      const double d = std::abs(prims[k].shape->signedDistance(r.voxels[i].center));
      if (d <= best) {
        best = d;
        source[i] = int(k);
      }
    }
  }
  hullmap::hulls::ConvexPartsParams params = r.params.convex_parts.value_or(hullmap::hulls::ConvexPartsParams{});
  if (!params.flat_gap) {
    params.flat_gap = r.report.cluster_params.used.eps;
    params.adapt_flat_gap = true;
  }
  if (r.report.floor.plane && std::abs(r.report.floor.plane->normal.z()) > 0.99 && !params.floor_z)
    params.floor_z = r.report.floor.plane->offset / r.report.floor.plane->normal.z();
  std::vector<V3> keyframes;
  for (const auto& k : r.keyframes) keyframes.push_back(k.position);
  std::vector<PartReach> out;
  for (const auto& o : r.obstacles) {
    // The cluster as it was split: its voxels and the stray parts' voxels that left it (now noise).
    std::vector<char> left(r.voxels.size(), 0);
    const auto& strays = r.report.parts->stray_voxels;
    for (std::size_t k = 0; k < strays.size(); ++k)
      if (r.report.parts->stray_obstacles[k] == o.id) left[strays[k]] = 1;
    std::vector<std::size_t> members;
    std::vector<V3> local;
    for (std::size_t i = 0; i < r.voxels.size(); ++i)
      if (r.clusters.labels[i] == o.id || left[i]) {
        members.push_back(i);
        local.push_back(r.voxels[i].center);
      }
    auto split = hullmap::hulls::splitConvexParts(local, res, params, keyframes);
    split.erase(std::remove_if(split.begin(), split.end(),
                               [&](const auto& g) {
                                 return std::all_of(g.begin(), g.end(),
                                                    [&](std::size_t m) { return left[members[m]]; });
                               }),
                split.end());
    EXPECT_EQ(split.size(), o.parts.size()) << "obstacle " << o.id;
    if (split.size() != o.parts.size()) continue;
    for (std::size_t p = 0; p < split.size(); ++p) {
      const auto& part = o.parts[p];
      EXPECT_EQ(split[p].size(), part.voxel_count) << "obstacle " << o.id << " part " << p;
      PartReach pr;
      pr.obstacle = o.id;
      pr.part = p;
      pr.voxels = split[p].size();
      pr.flat = part.flat;
      pr.faces = part.faces;
      pr.filled = part.filled;
      for (const std::size_t m : split[p]) {
        const int s = source[members[m]];
        if (s < 0) {
          ++pr.off_surface;
        } else if (std::find(pr.sources.begin(), pr.sources.end(), std::size_t(s)) == pr.sources.end()) {
          pr.sources.push_back(std::size_t(s));
        }
      }
      if (!pr.sources.empty()) {
        for (const V3& q : hullSamples(part.hull, part.aabb_min, part.aabb_max, pr.sources.size() > 1, 0.5 * res)) {
          if (truth.signedDistance(q) <= 0.0) continue;  // inside a true obstacle: no free space
          double d = std::numeric_limits<double>::infinity();
          for (const std::size_t s : pr.sources) d = std::min(d, prims[s].shape->signedDistance(q));
          if (d > pr.reach) {
            pr.reach = d;
            pr.where = q;
          }
        }
      }
      out.push_back(pr);
    }
  }
  return out;
}

TEST(RoomParts, WallPartsStayWithinConcavityPlusAVoxelOfTheirSurfaces) {
  // Pitch, monocular scale, density (half to twice V1_01's 45 points per m^2) and furniture varied.
  const std::vector<RoomCase> cases = {
      {31, 12, 0.37, 45, 12}, {32, 0, 0.3, 22, 16}, {33, 30, 3.0, 90, 9}, {34, 20, 1.0, 45, 14}};
  for (const RoomCase& c : cases) {
    SCOPED_TRACE(caseName(c));
    std::filesystem::path dir;
    const pipeline::BuildResult r = buildRoom(c, dir);
    const hullmap::sim::GroundTruth truth = hullmap::sim::readGroundTruth((dir / "ground_truth.json").string());
    const double res = r.map.resolution();
    const double bound = hullmap::hulls::defaultConcavity(res) + res;
    // The generator's 1 cm noise (3 sigma) and half a voxel's diagonal.
    const auto reaches = partReaches(r, truth, 0.03 + 0.5 * std::sqrt(3.0) * res);
    const auto prims = primitives(truth);
    std::size_t wall_parts = 0, over = 0;
    double worst_wall = 0.0, worst_other = 0.0;
    for (const auto& pr : reaches) {
      bool wall = false;
      for (const auto s : pr.sources) wall = wall || truth.shapes[prims[s].object].label.rfind("wall", 0) == 0;
      wall_parts += wall;
      (wall ? worst_wall : worst_other) = std::max(wall ? worst_wall : worst_other, pr.reach);
      if (!wall || pr.reach <= bound + 1e-9) continue;
      ++over;
      std::cout << caseName(c) << ": obstacle " << pr.obstacle << " part " << pr.part << " (" << pr.voxels
                << " voxels, " << pr.off_surface << " off every surface" << (pr.flat ? ", flat" : "")
                << (pr.faces ? ", faces" : "") << (pr.filled ? ", filled" : "") << ") reaches " << pr.reach << " at "
                << pr.where.transpose() << " from";
      for (const auto s : pr.sources) std::cout << " " << truth.shapes[prims[s].object].label;
      std::cout << "\n";
    }
    std::cout << caseName(c) << ": " << reaches.size() << " parts, " << wall_parts
              << " of them wall parts; farthest reach " << worst_wall << " (walls), " << worst_other
              << " (furniture); outlier voxels dropped " << r.report.cluster_params.trim.dropped << "\n";
    EXPECT_GT(wall_parts, 0u);
    EXPECT_EQ(over, 0u) << "wall parts reaching beyond T + a voxel (" << bound << ")";
  }
}

// Six rooms of docs/QUALITY.md's sweep (bench/quality.py's rooms_part: seeds 202, 205 and 221,
// at 22, 45 and 90 points per m^2; 220, at 5.3 % before the stray-part rule: most of its false
// alarms first met parts of stray voxels alone; 502 and 504, held out, which missed two deep
// collisions each before sparse edges: a table's corner, a box's edge and a cylinder's rim their
// last map points stopped short of), built at the defaults and checked as the issue does: 3000 random
// segments at r = 0.3 with their ends anywhere in the room; no deep collision missed, and at most 3 %
// of the segments keeping r + 0.15 from every true surface (the floor's too) called blocked.
TEST(RoomParts, SweepRoomsMissNoDeepCollisionAndAtMost3PercentFalseAlarms) {
  const std::vector<std::pair<RoomCase, double>> rooms = {{{202, 10, 1.0, 22, 9}, 0.0}, {{205, 0, 1.0, 45, 12}, 0.0},
                                                          {{221, 0, 3.0, 90, 16}, 0.5}, {{220, 30, 1.0, 45, 16}, 0.5},
                                                          {{502, 10, 1.0, 22, 9}, 0.0}, {{504, 30, 0.3, 22, 12}, 0.0}};
  for (const auto& [c, walls] : rooms) {
    SCOPED_TRACE(caseName(c));
    std::filesystem::path dir;
    const pipeline::BuildResult r = buildRoom(c, dir, walls);
    std::vector<V3> centers;
    std::vector<std::uint32_t> weights;
    for (const auto& v : r.voxels) {
      centers.push_back(v.center);
      weights.push_back(v.weight);
    }
    hullmap::sim::EvaluateParams params;
    params.segments = 3000;
    params.ends = hullmap::sim::SegmentEnds::kInTruthBox;
    params.clear_margin = 0.15;
    const hullmap::sim::Evaluation e = hullmap::sim::evaluate(
        r.obstacles, hullmap::sim::readGroundTruth((dir / "ground_truth.json").string()), centers, weights, params);
    std::cout << caseName(c) << " walls " << walls << ": deep " << e.deep << ", missed " << e.missed << "; clear "
              << e.clear << ", false alarms " << e.false_alarms << "\n";
    EXPECT_GT(e.deep, 500u);
    EXPECT_GT(e.clear, 500u);
    EXPECT_EQ(e.missed, 0u);
    EXPECT_LE(double(e.false_alarms), 0.03 * double(e.clear));
  }
}

}  // namespace
