// eps / minPts auto: the rule's invariance under scale, its clamps, and its outcome on generated
// scenes (surface voxels cluster, separate obstacles stay apart) and the real V1_01 map.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/clustering/auto_params.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/align.hpp"
#include "hullmap/mapper/floor.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace {

using hullmap::test::errorOf;
using namespace hullmap::clustering;
using hullmap::io::Points;
using hullmap::sim::TruthShape;

struct Voxels {
  std::vector<Eigen::Vector3d> centres;
  std::vector<std::uint32_t> weights;
};

// Occupied voxels of side `res` with their point counts (the oracle for the pipeline's voxel grid).
Voxels voxelize(const Points& points, double res) {
  std::map<std::tuple<long, long, long>, std::uint32_t> counts;
  for (const auto& p : points) {
    if (p.norm() > 1e4) continue;  // gross outliers: out of any octree's reach
    ++counts[{std::lround(std::floor(p.x() / res)), std::lround(std::floor(p.y() / res)),
              std::lround(std::floor(p.z() / res))}];
  }
  Voxels v;
  for (const auto& [k, n] : counts) {
    v.centres.emplace_back((std::get<0>(k) + 0.5) * res, (std::get<1>(k) + 0.5) * res, (std::get<2>(k) + 0.5) * res);
    v.weights.push_back(n);
  }
  return v;
}

double surfaceDistance(const TruthShape& o, const Eigen::Vector3d& p) {
  const Eigen::Vector3d h = 0.5 * o.size;
  const Eigen::Vector3d d = p - o.center;
  if (o.shape == TruthShape::Shape::kBox) {
    const Eigen::Vector3d q = d.cwiseAbs() - h;
    return std::abs(q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0));
  }
  const double radial = std::hypot(d.x(), d.y()) - h.x();
  const double axial = std::abs(d.z()) - h.z();
  return std::abs(std::hypot(std::max(radial, 0.0), std::max(axial, 0.0)) + std::min(std::max(radial, axial), 0.0));
}

TEST(ClusteringAutoParams, ScalesWithTheMapAndTheResolution) {
  hullmap::sim::SceneParams p;
  p.points = 8000;
  p.orbslam_frame = false;
  const auto scene = hullmap::sim::generateScene(p);
  const Voxels v = voxelize(scene.points, 0.05);
  const AutoParams base = chooseDbscanParams(v.centres, v.weights, 0.05);
  for (const double s : {4.0, 0.125, 3.7, 0.013}) {
    SCOPED_TRACE(s);
    std::vector<Eigen::Vector3d> scaled = v.centres;
    for (auto& c : scaled) c *= s;
    const AutoParams a = chooseDbscanParams(scaled, v.weights, 0.05 * s);
    EXPECT_NEAR(a.eps, base.eps * s, 1e-9 * a.eps);
    EXPECT_NEAR(a.knn, base.knn * s, 1e-9 * a.knn);
    EXPECT_EQ(a.min_pts, base.min_pts);
  }
  // Deterministic.
  const AutoParams again = chooseDbscanParams(v.centres, v.weights, 0.05);
  EXPECT_EQ(again.eps, base.eps);
  EXPECT_EQ(again.min_pts, base.min_pts);
}

TEST(ClusteringAutoParams, ClampsAndFollowsTheRuleOnALattice) {
  // A full 20 x 20 plane of voxels, weight 3 each: the 4th nearest voxel is 1 voxel away
  // (4 face neighbours), so with eps_factor 1.5 eps = max(1.5 * 1, 1.8) voxels; within 1.8 voxels
  // lie 9 voxels in the interior (3 x 3), 6 on the rim, 4 at the corners (not on a structure:
  // not more than k = 4).
  std::vector<Eigen::Vector3d> plane;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) plane.emplace_back(0.1 * i + 0.05, 0.1 * j + 0.05, 0.05);
  const std::vector<std::uint32_t> w(plane.size(), 3);
  AutoParamsRule rule;
  rule.eps_factor = 1.5;
  rule.min_pts_quantile = 0.25;
  const AutoParams a = chooseDbscanParams(plane, w, 0.1, Metric::kXyz, rule);
  EXPECT_NEAR(a.knn, 0.1, 1e-12);
  EXPECT_NEAR(a.eps, 0.18, 1e-12);
  EXPECT_EQ(a.min_pts, 27);  // 25% quantile of 72 rim (18) and 324 interior (27) voxels
  EXPECT_EQ(a.sampled, plane.size());
  EXPECT_EQ(a.structured, plane.size() - 4);
  rule.min_pts_quantile = 0.1;
  EXPECT_EQ(chooseDbscanParams(plane, w, 0.1, Metric::kXyz, rule).min_pts, 18);

  // A sparse lattice, one voxel in 6 along each axis: the 4th neighbour is 6 voxels away; 2 x 6 = 12
  // is clamped to 8 voxels; only the 4 face neighbours (6 voxels) and the voxel itself are in reach,
  // so only interior voxels are on a structure (5 > k), with weight 5.
  std::vector<Eigen::Vector3d> sparse;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) sparse.emplace_back(0.6 * i + 0.05, 0.6 * j + 0.05, 0.05);
  const AutoParams b = chooseDbscanParams(sparse, {}, 0.1);
  EXPECT_NEAR(b.knn, 0.6, 1e-12);
  EXPECT_NEAR(b.eps, 0.8, 1e-12);
  EXPECT_EQ(b.min_pts, 5);
  EXPECT_EQ(b.structured, 18u * 18u);

  // Alone: nothing within reach.
  const AutoParams c = chooseDbscanParams({{0, 0, 0}}, {}, 0.05);
  EXPECT_TRUE(std::isinf(c.knn));
  EXPECT_NEAR(c.eps, 0.4, 1e-12);
  EXPECT_EQ(c.min_pts, 3);
  const AutoParams empty = chooseDbscanParams({}, {}, 0.05);
  EXPECT_NEAR(empty.eps, 0.09, 1e-12);
}

TEST(ClusteringAutoParams, RejectsBadInput) {
  EXPECT_NE(errorOf([] { chooseDbscanParams({}, {}, 0.0); }).rfind("eps: auto: ", 0), std::string::npos);
  EXPECT_NE(errorOf([] { chooseDbscanParams({{0, 0, 0}}, {1, 2}, 0.05); }).find("weights"), std::string::npos);
  EXPECT_NE(errorOf([] { chooseDbscanParams({{0, 0, NAN}}, {}, 0.05); }).find("non-finite"), std::string::npos);
  AutoParamsRule r;
  r.max_eps_voxels = 1.0;
  EXPECT_NE(errorOf([&] { chooseDbscanParams({}, {}, 0.05, Metric::kXyz, r); }).find("clamp"), std::string::npos);
  r = {};
  r.min_pts_quantile = 2.0;
  EXPECT_NE(errorOf([&] { chooseDbscanParams({}, {}, 0.05, Metric::kXyz, r); }).find("quantile"), std::string::npos);
}

// On generated scenes of several densities, the chosen parameters leave few obstacle voxels as
// noise, never join two obstacles (0.5 m apart), and keep pure outliers out of clusters mostly.
TEST(ClusteringAutoParams, GeneratedScenesClusterWithLittleNoiseAndNoMerges) {
  for (const std::size_t points : {5000u, 20000u, 200000u}) {
    SCOPED_TRACE(points);
    hullmap::sim::SceneParams p;
    p.points = points;
    p.orbslam_frame = false;
    const auto scene = hullmap::sim::generateScene(p);
    const Voxels v = voxelize(scene.points, 0.05);
    const AutoParams a = chooseDbscanParams(v.centres, v.weights, 0.05);
    DbscanParams params;
    params.eps = a.eps;
    params.min_pts = a.min_pts;
    const DbscanResult r = dbscan(v.centres, v.weights, params);

    std::size_t on_obstacle = 0, on_obstacle_noise = 0;
    std::map<std::int32_t, std::set<std::size_t>> touched;  // cluster -> true obstacles
    for (std::size_t i = 0; i < v.centres.size(); ++i) {
      for (std::size_t o = 0; o < scene.truth.shapes.size(); ++o) {
        if (surfaceDistance(scene.truth.shapes[o], v.centres[i]) <= 0.06) {
          ++on_obstacle;
          if (r.labels[i] == kNoise)
            ++on_obstacle_noise;
          else
            touched[r.labels[i]].insert(o);
        }
      }
    }
    std::size_t merged = 0;
    for (const auto& [label, obstacles] : touched) merged += obstacles.size() > 1;
    const double noise_share = static_cast<double>(on_obstacle_noise) / static_cast<double>(on_obstacle);
    std::cout << points << " points, " << v.centres.size() << " voxels: eps " << a.eps << " minPts " << a.min_pts
              << " (k-NN " << a.knn << "): " << r.cluster_sizes.size() << " clusters, " << touched.size()
              << " on obstacles, obstacle-voxel noise " << noise_share << ", merged " << merged << "\n";
    EXPECT_EQ(merged, 0u);
    EXPECT_LT(noise_share, 0.05);
    EXPECT_LE(touched.size(), 2 * scene.truth.shapes.size());
  }
}

// Realistic rooms (walls, floor, L-shelves, tables; sparse): with the floor found and left out,
// the walls form about one cluster (they meet at the corners) and each piece of furniture about
// its own; no piece joins another or a wall; few of their voxels are noise.
TEST(ClusteringAutoParams, RealisticRoomsClusterIntoWallsAndFurniture) {
  for (const double density : {30.0, 80.0, 200.0}) {
    SCOPED_TRACE(density);
    hullmap::sim::SceneParams p;
    p.layout = hullmap::sim::SceneLayout::kRoom;
    p.density = density;
    p.orbslam_frame = false;
    const auto scene = hullmap::sim::generateScene(p);
    const hullmap::mapper::PlaneFit floor =
        hullmap::mapper::findBoundingPlane(scene.points, hullmap::mapper::PlaneSide::kFloor);
    ASSERT_TRUE(floor.found) << floor.reason;
    const Voxels all = voxelize(scene.points, 0.05);
    const auto classes = hullmap::mapper::classifySurfaces(all.centres, floor.plane, std::nullopt, 0.05);
    Voxels v;
    for (std::size_t i = 0; i < all.centres.size(); ++i) {
      if (classes[i] != hullmap::mapper::SurfaceClass::kObstacle) continue;
      v.centres.push_back(all.centres[i]);
      v.weights.push_back(all.weights[i]);
    }
    const AutoParams a = chooseDbscanParams(v.centres, v.weights, 0.05);
    DbscanParams params;
    params.eps = a.eps;
    params.min_pts = a.min_pts;
    const DbscanResult r = dbscan(v.centres, v.weights, params);

    // Objects 1-4 are the walls (one structure), 5... the furniture.
    std::size_t on_object = 0, noise = 0;
    std::map<std::int32_t, std::set<std::size_t>> touched;
    for (std::size_t i = 0; i < v.centres.size(); ++i) {
      for (std::size_t o = 1; o < scene.truth.shapes.size(); ++o) {
        bool hit = false;
        for (const auto& part : scene.truth.shapes[o].primitives())
          hit = hit || surfaceDistance(part, v.centres[i]) <= 0.06;
        if (!hit) continue;
        ++on_object;
        if (r.labels[i] == kNoise)
          ++noise;
        else
          touched[r.labels[i]].insert(o < 5 ? 1 : o);
      }
    }
    std::size_t merged = 0;
    std::map<std::size_t, std::size_t> fragments;  // object -> clusters touching it
    for (const auto& [label, objects] : touched) {
      merged += objects.size() > 1;
      for (std::size_t o : objects) ++fragments[o];
    }
    for (const auto& [o, count] : fragments) {
      if (count > 1)
        std::cout << "  object " << o << " (" << scene.truth.shapes[o].kind << ") in " << count << " clusters\n";
    }
    const double noise_share = static_cast<double>(noise) / static_cast<double>(on_object);
    std::cout << "room " << density << " points/m^2, " << v.centres.size() << " voxels: eps " << a.eps << " minPts "
              << a.min_pts << ": " << touched.size() << " clusters on objects (walls + " << p.obstacles
              << " furniture), object-voxel noise " << noise_share << ", merged " << merged << "\n";
    EXPECT_EQ(merged, 0u);
    EXPECT_LT(noise_share, 0.02);
    // Every object is found, in one or two clusters (the walls may part at a corner, a table's leg
    // from its top).
    EXPECT_EQ(fragments.size(), 1 + p.obstacles);
    for (const auto& [o, count] : fragments) EXPECT_LE(count, 2u) << o;
    EXPECT_LE(touched.size(), 1 + p.obstacles + 2);
  }
}

TEST(ClusteringAutoParams, RealEurocV101FewVoxelsAreNoise) {
  HULLMAP_REQUIRE_REAL_DATA(path, "orbslam2_euroc_V1_01_MapPoints.txt");
  auto set = hullmap::io::readPointFile(path);
  hullmap::mapper::toMapFrame(hullmap::mapper::FrameParams{hullmap::mapper::UpAxis::kNegY, 1.0}, set.points);
  const Voxels v = voxelize(set.points, 0.05);
  const AutoParams a = chooseDbscanParams(v.centres, v.weights, 0.05);
  DbscanParams params;
  params.eps = a.eps;
  params.min_pts = a.min_pts;
  const DbscanResult r = dbscan(v.centres, v.weights, params);
  const double noise_share = static_cast<double>(r.noise) / static_cast<double>(v.centres.size());
  std::cout << "V1_01: " << v.centres.size() << " voxels, eps " << a.eps << " minPts " << a.min_pts << ": "
            << r.cluster_sizes.size() << " clusters, noise " << noise_share << " (eps 0.1 / minPts 10: 58%)\n";
  EXPECT_LT(noise_share, 0.10);
  EXPECT_GE(a.eps, 0.09);
  EXPECT_LE(a.eps, 0.4);
}

}  // namespace

namespace {

// The pieces together on maps/room (a realistic room in the first camera's frame, monocular
// scale): align the keyframes to the reference (metres, z up), find the floor (level), leave its
// voxels out, choose eps/minPts from the rest, cluster: the walls and each piece of furniture.
TEST(ClusteringAutoParams, MapsRoomAlignedLevelledAndClustered) {
  namespace m = hullmap::mapper;
  namespace io = hullmap::io;
  const std::filesystem::path dir = std::filesystem::path(HULLMAP_SOURCE_DIR) / "maps" / "room";
  auto points = io::readPointFile((dir / "map_points.txt").string()).points;
  const auto keyframes = io::readTumTrajectory((dir / "KeyFrameTrajectory.txt").string());
  const auto reference =
      io::readReferenceTrajectory((dir / "reference_trajectory.txt").string(), io::ReferenceFormat::kTum);
  const m::Alignment alignment = m::alignTrajectory(keyframes, reference);
  EXPECT_NEAR(alignment.transform.scale, 1.0 / 0.37, 1e-6);
  m::applySimilarity(alignment.transform, points);

  m::PlaneSearchParams floor_params;
  floor_params.fit_tilt = false;  // aligned: the reference defines up
  const m::PlaneFit floor = m::findBoundingPlane(points, m::PlaneSide::kFloor, floor_params);
  ASSERT_TRUE(floor.found) << floor.reason;
  EXPECT_NEAR(floor.plane.offset, 0.0, 0.01);

  const Voxels all = voxelize(points, 0.05);
  const auto classes = m::classifySurfaces(all.centres, floor.plane, std::nullopt, 0.05);
  Voxels v;
  for (std::size_t i = 0; i < all.centres.size(); ++i) {
    if (classes[i] != m::SurfaceClass::kObstacle) continue;
    v.centres.push_back(all.centres[i]);
    v.weights.push_back(all.weights[i]);
  }
  const AutoParams a = chooseDbscanParams(v.centres, v.weights, 0.05);
  DbscanParams params;
  params.eps = a.eps;
  params.min_pts = a.min_pts;
  const DbscanResult r = dbscan(v.centres, v.weights, params);
  std::size_t big = 0;
  for (std::size_t size : r.cluster_sizes) big += size >= 10;
  std::cout << "maps/room: scale " << alignment.transform.scale << ", floor at " << floor.plane.offset << ", "
            << all.centres.size() - v.centres.size() << " floor voxels of " << all.centres.size() << "; eps " << a.eps
            << " minPts " << a.min_pts << ": " << r.cluster_sizes.size() << " clusters (" << big
            << " of 10+ voxels), noise " << r.noise << "\n";
  // Walls (one ring, or parted at a corner) + 8 pieces of furniture, each maybe in two.
  EXPECT_GE(big, 9u);
  EXPECT_LE(big, 12u);
  EXPECT_LT(static_cast<double>(r.noise) / static_cast<double>(v.centres.size()), 0.08);
}

}  // namespace

namespace {

// However sparse the map, eps stays at most 8 voxels (0.4 m at 5 cm): two very sparse walls 0.5 m
// apart, with 1 cm noise, stay two clusters.
TEST(ClusteringAutoParams, SparseWallsHalfAMetreApartStaySeparate) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  std::normal_distribution<double> n(0.0, 0.01);
  for (const double density : {5.0, 15.0, 60.0}) {  // points per m^2
    SCOPED_TRACE(density);
    Points pts;
    for (int i = 0; i < static_cast<int>(density * 9.0); ++i) {
      pts.emplace_back(n(rng), u(rng), u(rng));
      pts.emplace_back(0.5 + n(rng), u(rng), u(rng));
    }
    const Voxels v = voxelize(pts, 0.05);
    const AutoParams a = chooseDbscanParams(v.centres, v.weights, 0.05);
    EXPECT_LE(a.eps, 0.4 + 1e-12);
    DbscanParams params;
    params.eps = a.eps;
    params.min_pts = a.min_pts;
    const DbscanResult r = dbscan(v.centres, v.weights, params);
    std::set<std::int32_t> left, right;
    for (std::size_t i = 0; i < v.centres.size(); ++i) {
      if (r.labels[i] == kNoise) continue;
      (v.centres[i].x() < 0.25 ? left : right).insert(r.labels[i]);
    }
    for (std::int32_t label : left) EXPECT_EQ(right.count(label), 0u) << "a cluster spans both walls";
    EXPECT_FALSE(left.empty());
    EXPECT_FALSE(right.empty());
    std::cout << density << " points/m^2: eps " << a.eps << " minPts " << a.min_pts << ", clusters "
              << r.cluster_sizes.size() << ", noise " << r.noise << " of " << v.centres.size() << "\n";
  }
}

}  // namespace
