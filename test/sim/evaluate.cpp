// evaluate: truth geometry against brute-force oracles; hand-built cases with known answers; the
// CLI's exit codes.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "evaluate_fixtures.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/evaluate.hpp"
#include "test_support.hpp"

namespace hullmap::sim {
namespace {

using V3 = Eigen::Vector3d;

TruthShape box(const V3& center, const V3& size, double yaw = 0.0, const std::string& kind = "box") {
  TruthShape s = TruthShape::box(center, size, kind, yaw);
  s.aabb_min = center - size;  // loose is fine for these tests
  s.aabb_max = center + size;
  return s;
}

/// Points on a shape's surface at spacing `step`: `inside(p)` decides membership, the surface is
/// where a grid point is in and a neighbour out (brute force on a fine grid).
std::vector<V3> surfaceSamples(const std::function<bool(const V3&)>& inside, const V3& lo, const V3& hi, double step) {
  std::vector<V3> out;
  for (double x = lo.x(); x <= hi.x(); x += step)
    for (double y = lo.y(); y <= hi.y(); y += step)
      for (double z = lo.z(); z <= hi.z(); z += step) {
        const V3 p(x, y, z);
        if (!inside(p)) continue;
        for (const V3& d :
             {V3(step, 0, 0), V3(-step, 0, 0), V3(0, step, 0), V3(0, -step, 0), V3(0, 0, step), V3(0, 0, -step)})
          if (!inside(p + d)) {
            out.push_back(p);
            break;
          }
      }
  return out;
}

void expectMatchesOracle(const TruthShape& shape, const std::function<bool(const V3&)>& inside, double step) {
  const std::vector<V3> surface = surfaceSamples(inside, V3::Constant(-1.5), V3::Constant(1.5), step);
  ASSERT_FALSE(surface.empty());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.4, 1.4);
  for (int k = 0; k < 300; ++k) {
    const V3 p(u(rng), u(rng), u(rng));
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& s : surface) nearest = std::min(nearest, (p - s).norm());
    const double oracle = inside(p) ? -nearest : nearest;
    EXPECT_NEAR(shape.signedDistance(p), oracle, 2.0 * step) << p.transpose();
  }
}

TEST(TruthGeometry, BoxMatchesBruteForce) {
  const TruthShape b = box(V3(0.1, -0.2, 0.05), V3(1.0, 0.6, 0.8), 0.5);
  const double c = std::cos(0.5), s = std::sin(0.5);
  expectMatchesOracle(
      b,
      [&](const V3& p) {
        const V3 d = p - b.center;
        const V3 local(c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z());
        return (local.cwiseAbs().array() <= 0.5 * b.size.array()).all();
      },
      0.04);
}

TEST(TruthGeometry, CylinderMatchesBruteForce) {
  const TruthShape cyl = TruthShape::cylinder(V3(0.1, 0.0, -0.1), V3(1.2, 1.2, 1.0));
  expectMatchesOracle(
      cyl,
      [&](const V3& p) {
        const V3 d = p - cyl.center;
        return std::hypot(d.x(), d.y()) <= 0.6 && std::abs(d.z()) <= 0.5;
      },
      0.04);
}

/// The 12 triangles of a box, outward.
std::string boxObj(const V3& lo, const V3& hi) {
  std::ostringstream out;
  out << "o crate\n";
  for (int m = 0; m < 8; ++m)
    out << "v " << ((m & 1) ? hi.x() : lo.x()) << ' ' << ((m & 2) ? hi.y() : lo.y()) << ' '
        << ((m & 4) ? hi.z() : lo.z()) << '\n';
  // Quads, counter-clockwise from outside, 1-based.
  out << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  return out.str();
}

TEST(TruthGeometry, MeshOfABoxIsTheBox) {
  const auto dir = test::freshDir("mesh");
  const std::string path = (dir / "crate.obj").string();
  std::ofstream(path) << boxObj(V3(-0.5, -0.3, 0.0), V3(0.5, 0.3, 0.4));
  const GroundTruth truth = readGroundTruth(path);
  ASSERT_EQ(truth.shapes.size(), 1u);
  EXPECT_EQ(truth.shapes[0].label, "crate");
  const TruthShape b = box(V3(0, 0, 0.2), V3(1.0, 0.6, 0.4));
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 500; ++k) {
    const V3 p(u(rng), u(rng), u(rng));
    EXPECT_NEAR(truth.shapes[0].signedDistance(p), b.signedDistance(p), 1e-9) << p.transpose();
  }
}

std::vector<V3> boxSurface(const V3& lo, const V3& hi) {
  std::vector<V3> out;
  for (double x = lo.x(); x <= hi.x() + 1e-9; x += 0.1)
    for (double y = lo.y(); y <= hi.y() + 1e-9; y += 0.1) {
      out.emplace_back(x, y, lo.z());
      out.emplace_back(x, y, hi.z());
    }
  return out;
}

TEST(TruthGeometry, UnionIsExactOutsideAndInsideWhereItsPartsAre) {
  // An L of two touching boxes, read from JSON as `generate --layout room` writes it; the oracle is
  // the brute-force distance to the L's surface samples (exact outside; inside only the sign is
  // promised, the depth may be smaller near the face the arms share).
  const auto dir = test::freshDir("union");
  std::ofstream(dir / "l.json") << R"({"obstacles": [{"kind": "l_shelf", "shape": "union", "parts": [
      {"shape": "box", "center": [0, 0, 0], "size": [2, 1, 1]},
      {"shape": "box", "center": [0.5, 1, 0], "size": [1, 1, 1]}]}]})";
  const GroundTruth truth = readGroundTruth((dir / "l.json").string());
  ASSERT_EQ(truth.shapes.size(), 1u);
  const TruthShape& l = truth.shapes[0];
  EXPECT_EQ(l.shape, TruthShape::Shape::kUnion);
  EXPECT_EQ(l.kind, "l_shelf");
  EXPECT_EQ(l.label, "l_shelf 0");
  EXPECT_TRUE(l.aabb_min.isApprox(V3(-1, -0.5, -0.5)));
  EXPECT_TRUE(l.aabb_max.isApprox(V3(1, 1.5, 0.5)));
  const auto inside = [](const V3& p) {
    const bool a = std::abs(p.x()) <= 1 && std::abs(p.y()) <= 0.5 && std::abs(p.z()) <= 0.5;
    const bool b = std::abs(p.x() - 0.5) <= 0.5 && std::abs(p.y() - 1) <= 0.5 && std::abs(p.z()) <= 0.5;
    return a || b;
  };
  const double step = 0.05;
  const std::vector<V3> surface = surfaceSamples(inside, V3(-1.5, -1, -1), V3(1.5, 2, 1), step);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.4, 1.9);
  int outside = 0;
  for (int k = 0; k < 400; ++k) {
    const V3 p(u(rng), u(rng), u(rng) * 0.6);
    const double d = l.signedDistance(p);
    if (inside(p)) {
      EXPECT_LE(d, 0.0) << p.transpose();
      continue;
    }
    ++outside;
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& s : surface) nearest = std::min(nearest, (p - s).norm());
    EXPECT_NEAR(d, nearest, 2.0 * step) << p.transpose();
  }
  EXPECT_GT(outside, 100);

  std::ofstream(dir / "empty.json") << R"({"obstacles": [{"shape": "union", "parts": []}]})";
  EXPECT_THROW(readGroundTruth((dir / "empty.json").string()), Error);
  std::ofstream(dir / "nested.json") << R"({"obstacles": [{"shape": "union", "parts": [{"shape": "union"}]}]})";
  EXPECT_THROW(readGroundTruth((dir / "nested.json").string()), Error);
}

TEST(Evaluate, SegmentsStayAboveATrueFloor) {
  // Truth: a floor slab (top z = 0) and a pillar on it; the hulls hold the pillar only, as a build
  // that takes the floor out of its obstacles. Segments everywhere cross the floor (missed); with the
  // slab marked as the floor ("kind": "floor") they keep r + clear_margin above it, not even beside
  // its edge coming near it.
  GroundTruth truth;
  truth.shapes.push_back(box(V3(0.5, 0.5, -0.05), V3(2, 2, 0.1)));
  truth.shapes.push_back(box(V3(0.5, 0.5, 1), V3(1, 1, 2)));
  const std::vector<hulls::Obstacle> obstacles{test::filledObstacle(V3(0, 0, 0), V3(1, 1, 2), 0)};
  EvaluateParams params;
  params.segments = 6000;
  const Evaluation everywhere = evaluate(obstacles, truth, {}, {}, params);
  EXPECT_GT(everywhere.missed, 0u);
  truth.shapes[0] = box(V3(0.5, 0.5, -0.05), V3(2, 2, 0.1), 0.0, "floor");
  ASSERT_TRUE(truth.shapes[0].surface);
  const Evaluation above = evaluate(obstacles, truth, {}, {}, params);
  EXPECT_EQ(above.segments, 6000u);
  EXPECT_GE(above.deep, 5u);
  EXPECT_EQ(above.missed, 0u);
  EXPECT_EQ(above.false_alarms, 0u);
}

TEST(Evaluate, ExactHullHasNothingToReport) {
  GroundTruth truth;
  truth.shapes.push_back(box(V3(0.5, 0.5, 0.5), V3(1, 1, 1)));
  const std::vector<hulls::Obstacle> obstacles{test::filledObstacle(V3(0, 0, 0), V3(1, 1, 1), 0)};
  EvaluateParams params;
  const Evaluation e = evaluate(obstacles, truth, boxSurface(V3(0, 0, 0), V3(1, 1, 1)), {}, params);
  ASSERT_EQ(e.truth.size(), 1u);
  EXPECT_GT(e.truth[0].points_near, 100);
  EXPECT_EQ(e.truth[0].points_inside, e.truth[0].points_near);
  EXPECT_EQ(e.truth[0].parts_touching.size(), 1u);
  EXPECT_TRUE(e.false_parts.empty());
  EXPECT_NEAR(e.hull_volume, 1.0, 1e-9);
  EXPECT_EQ(e.outside_volume, 0.0);
  EXPECT_EQ(e.far_volume, 0.0);
  EXPECT_EQ(e.segments, 2000u);
  EXPECT_GT(e.deep, 10u);
  EXPECT_GT(e.clear, 100u);
  EXPECT_EQ(e.missed, 0u);
  EXPECT_EQ(e.false_alarms, 0u);
}

TEST(Evaluate, AMarginCatchesWhatAShortHullMisses) {
  // A hull 0.15 short of the true cube on every side, as a sparse sample's hull falls short of its
  // object's edges: deep segments (within R - 0.1 = 0.2 of the cube) pass up to 0.2 + 0.15 sqrt(3)
  // = 0.46 from the hull (at a corner), so at R some are missed; checked at R + 0.17 none can be. The
  // segments and their classes do not depend on the margin, and a margin only adds collisions.
  GroundTruth truth;
  truth.shapes.push_back(box(V3(0.5, 0.5, 0.5), V3(1, 1, 1)));
  const std::vector<hulls::Obstacle> obstacles{test::filledObstacle(V3(0.15, 0.15, 0.15), V3(0.85, 0.85, 0.85), 0)};
  EvaluateParams params;
  params.segments = 3000;
  const std::vector<V3> points = boxSurface(V3(0, 0, 0), V3(1, 1, 1));
  const Evaluation plain = evaluate(obstacles, truth, points, {}, params);
  params.margin = 0.17;
  const Evaluation safe = evaluate(obstacles, truth, points, {}, params);
  EXPECT_GT(plain.missed, 0u);
  EXPECT_EQ(safe.missed, 0u);
  EXPECT_EQ(safe.deep, plain.deep);
  EXPECT_EQ(safe.clear, plain.clear);
  EXPECT_GE(safe.false_alarms, plain.false_alarms);
  params.margin = -0.01;
  EXPECT_THROW(evaluate(obstacles, truth, points, {}, params), Error);
}

TEST(Evaluate, SwallowedVolumeMatchesTheAnalyticValue) {
  // Truth: the unit cube. Hull: [0, 2] x [0, 1] x [0, 1], swallowing 1 m^3, of which 0.9 m^3 is
  // farther than 0.1 from the cube; and a hull 5 m away touching nothing.
  GroundTruth truth;
  truth.shapes.push_back(box(V3(0.5, 0.5, 0.5), V3(1, 1, 1)));
  const std::vector<hulls::Obstacle> obstacles{test::filledObstacle(V3(0, 0, 0), V3(2, 1, 1), 0),
                                               test::filledObstacle(V3(5, 0, 0), V3(5.5, 0.5, 0.5), 1)};
  EvaluateParams params;
  params.segments = 500;
  params.volume_samples = 20000;
  const Evaluation e = evaluate(obstacles, truth, {}, {}, params);
  EXPECT_NEAR(e.union_volume, 2.125, 1e-9);  // every sample is in one hull only
  EXPECT_GT(e.outside_volume_se, 0.0);
  EXPECT_NEAR(e.outside_volume, 1.0 + 0.125, 4 * e.outside_volume_se);
  EXPECT_NEAR(e.far_volume, 0.9 + 0.125, 4 * e.far_volume_se);
  ASSERT_EQ(e.false_parts.size(), 1u);
  EXPECT_EQ(e.false_parts[0].obstacle, 1);
  EXPECT_NEAR(e.false_parts[0].distance, 4.0, 1e-9);
  EXPECT_NEAR(e.false_parts[0].volume, 0.125, 1e-9);
  EXPECT_NEAR(e.false_volume, 0.125, 1e-9);
  EXPECT_EQ(e.missed, 0u);
  EXPECT_GT(e.false_alarms, 0u);  // segments over the swallowed half
}

TEST(Evaluate, FalsePartsAtAToleranceWithTheirDistanceMatchBruteForce) {
  // A rotated box and a cylinder; cubes of 1 to 3 voxels (0.1 m) strewn around them. A cube is a
  // false part when its hull comes no closer than the tolerance to either; its distance is the
  // exact hull-to-shape distance, against the least over a 5 mm grid inside the cube (which lies
  // within 5 mm * sqrt(3) / 2 of the nearest point).
  GroundTruth truth;
  truth.shapes.push_back(box(V3(0.0, 0.0, 0.5), V3(1.0, 0.6, 1.0), 0.4));
  TruthShape cyl = TruthShape::cylinder(V3(1.6, 0.2, 0.4), V3(0.5, 0.5, 0.8));
  cyl.aabb_min = cyl.center - cyl.size;
  cyl.aabb_max = cyl.center + cyl.size;
  truth.shapes.push_back(cyl);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 2.5), z(-0.2, 1.2);
  std::uniform_int_distribution<int> side(1, 3);
  std::vector<hulls::Obstacle> obstacles;
  std::vector<double> oracle;
  const double tolerance = 0.05;
  while (obstacles.size() < 60) {
    const V3 lo(std::round(u(rng) * 20) / 20, std::round(u(rng) * 20) / 20, std::round(z(rng) * 20) / 20);
    const V3 hi = lo + 0.1 * V3(side(rng), side(rng), side(rng));
    double nearest = std::numeric_limits<double>::infinity();
    for (double x = lo.x(); x <= hi.x() + 1e-9; x += 0.005)
      for (double y = lo.y(); y <= hi.y() + 1e-9; y += 0.005)
        for (double w = lo.z(); w <= hi.z() + 1e-9; w += 0.005)
          nearest = std::min(nearest, truth.signedDistance(V3(x, y, w)));
    nearest = std::max(nearest, 0.0);
    if (std::abs(nearest - tolerance) < 0.01) continue;  // too close to the tolerance for the grid to say
    obstacles.push_back(test::filledObstacle(lo, hi, int(obstacles.size())));
    oracle.push_back(nearest);
  }
  EvaluateParams params;
  params.segments = 0;
  params.volume_samples = 200;
  params.false_tolerance = tolerance;
  const Evaluation e = evaluate(obstacles, truth, {}, {}, params);
  std::size_t expected = 0;
  double volume = 0.0;
  for (std::size_t k = 0; k < oracle.size(); ++k) {
    const auto it = std::find_if(e.false_parts.begin(), e.false_parts.end(),
                                 [&](const FalsePart& f) { return f.obstacle == int(k); });
    EXPECT_EQ(it != e.false_parts.end(), oracle[k] > tolerance) << k << ": brute force " << oracle[k];
    if (it == e.false_parts.end()) continue;
    ++expected;
    volume += obstacles[k].volume;
    EXPECT_LE(it->distance, oracle[k] + 1e-9) << k;
    EXPECT_GE(it->distance, oracle[k] - 0.005) << k;
    EXPECT_NEAR(it->volume, obstacles[k].volume, 1e-12) << k;
    EXPECT_EQ(it->part, -1);
  }
  EXPECT_EQ(e.false_parts.size(), expected);
  EXPECT_GT(expected, 5u);
  EXPECT_LT(expected, oracle.size());
  EXPECT_NEAR(e.false_volume, volume, 1e-9);
  const auto json = evaluationToJson(e, params);
  EXPECT_EQ(json["parameters"]["false_tolerance"], tolerance);
  ASSERT_EQ(json["false_parts"].size(), expected);
  EXPECT_TRUE(json["false_parts"][0].contains("distance"));
  EXPECT_TRUE(json["false_parts"][0].contains("volume"));
}

TEST(Evaluate, SameSeedSameNumbers) {
  GroundTruth truth;
  truth.shapes.push_back(box(V3(0.5, 0.5, 0.5), V3(1, 1, 1)));
  const std::vector<hulls::Obstacle> obstacles{test::filledObstacle(V3(0, 0, 0), V3(2, 1, 1), 0)};
  EvaluateParams params;
  params.segments = 200;
  const auto a = evaluationToJson(evaluate(obstacles, truth, {}, {}, params), params);
  const auto b = evaluationToJson(evaluate(obstacles, truth, {}, {}, params), params);
  EXPECT_EQ(a, b);
}

TEST(Evaluate, PartsStopSwallowingTheRoom) {
  // maps/simple at eps 0.2 / minPts 3 (fewer fragments, but clusters that bridge free space): whole
  // hulls against convex parts at the default T, scored against the room's truth. Prints both.
  hullmap::pipeline::BuildParams build;
  build.inputs = {std::string(HULLMAP_SOURCE_DIR) + "/maps/simple/map_points.txt"};
  build.frame.up = hullmap::mapper::parseUpAxis("-y");
  build.eps = 0.2;
  build.min_pts = 3;
  build.floor.mode = hullmap::mapper::PlaneSetting::Mode::kNone;  // whole clusters, split below
  build.convex_parts.reset();
  hullmap::pipeline::BuildResult r = hullmap::pipeline::build(build);
  const GroundTruth truth = readGroundTruth(std::string(HULLMAP_SOURCE_DIR) + "/maps/simple/ground_truth.json");
  std::vector<V3> centers;
  std::vector<std::uint32_t> weights;
  for (const auto& v : r.voxels) {
    centers.push_back(v.center);
    weights.push_back(v.weight);
  }
  const EvaluateParams params;
  const Evaluation whole = evaluate(r.obstacles, truth, centers, weights, params);
  hulls::addConvexParts(r.obstacles, centers, weights, r.clusters.labels, r.map.resolution(), {});
  const Evaluation parts = evaluate(r.obstacles, truth, centers, weights, params);
  for (const auto* e : {&whole, &parts})
    std::cout << (e == &whole ? "whole hulls: " : "convex parts: ") << e->parts << " hulls, " << e->false_parts.size()
              << " false; union " << e->union_volume << " m^3, farther than 0.1 m from the truth " << e->far_volume
              << " +- " << e->far_volume_se << "; deep " << e->deep << " missed " << e->missed << "; clear " << e->clear
              << " false alarms " << e->false_alarms << "\n";
  EXPECT_EQ(parts.missed, 0u);
  EXPECT_LE(parts.far_volume, whole.far_volume);
  EXPECT_LE(parts.false_alarms, whole.false_alarms);
  double near = 0, inside = 0;
  for (const auto& t : parts.truth) {
    near += t.points_near;
    inside += t.points_inside;
  }
  EXPECT_GT(inside, 0.95 * near);  // splitting keeps every clustered voxel in some part
}

/// Points on the six faces of the box [lo, hi] at the centres of a grid of cells of about `step`.
std::vector<V3> faceSamples(const V3& lo, const V3& hi, double step) {
  std::vector<V3> out;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const int nu = std::max(1, int(std::lround((hi[u] - lo[u]) / step)));
    const int nv = std::max(1, int(std::lround((hi[v] - lo[v]) / step)));
    for (const double side : {lo[axis], hi[axis]})
      for (int a = 0; a < nu; ++a)
        for (int b = 0; b < nv; ++b) {
          V3 p;
          p[axis] = side;
          p[u] = lo[u] + (a + 0.5) * (hi[u] - lo[u]) / nu;
          p[v] = lo[v] + (b + 0.5) * (hi[v] - lo[v]) / nv;
          out.push_back(p);
        }
  }
  return out;
}

TruthShape aabb(const V3& lo, const V3& hi) { return box(0.5 * (lo + hi), hi - lo); }

TEST(Evaluate, APointBelongsToItsNearestShapeOnly) {
  // A floor slab (top z = 0) and a wall standing on it (x in [0, 0.25]). Floor points 3 cm in front
  // of the wall lie on the floor (distance 0) though within surface_margin of the wall: they are the
  // floor's, not the wall's; the wall's own points 3 cm above the floor are the wall's. The hull
  // holds the wall exactly, so the wall's share is 100% (it was 50% when points counted for every
  // shape within the margin). A point exactly as far from both goes to the lower index.
  GroundTruth truth;
  truth.shapes.push_back(aabb(V3(-1, -1, -0.125), V3(1, 1, 0)));
  truth.shapes.push_back(aabb(V3(0, -1, 0), V3(0.25, 1, 1)));
  const std::vector<hulls::Obstacle> obstacles{test::filledObstacle(V3(0, -1, 0), V3(0.3, 1, 1), 0)};
  std::vector<V3> points;
  for (double y = -0.95; y < 1; y += 0.1) {
    points.emplace_back(-0.03, y, 0.0);  // floor, in front of the wall's foot
    points.emplace_back(0.0, y, 0.03);   // wall face, just above the floor
  }
  const std::size_t pairs = points.size() / 2;
  points.emplace_back(-0.03125, 0.0, 0.03125);  // 0.03125 from both, exactly
  EvaluateParams params;
  params.segments = 0;
  Evaluation e = evaluate(obstacles, truth, points, {}, params);
  EXPECT_EQ(e.truth[0].points_near, double(pairs + 1));
  EXPECT_EQ(e.truth[0].points_inside, 0.0);
  EXPECT_EQ(e.truth[1].points_near, double(pairs));
  EXPECT_EQ(e.truth[1].points_inside, double(pairs));
  std::swap(truth.shapes[0], truth.shapes[1]);  // the tie follows the index
  e = evaluate(obstacles, truth, points, {}, params);
  EXPECT_EQ(e.truth[0].points_near, double(pairs + 1));
  EXPECT_EQ(e.truth[1].points_near, double(pairs));
}

TEST(Evaluate, AttributionAndRepresentationMatchBruteForce) {
  // Overlapping and touching axis-aligned boxes, points scattered within 8 cm of their surfaces with
  // integer weights, hulls that are boxes on the 0.1 lattice. The oracle: the axis-aligned box
  // distance written out, the nearest shape by a plain scan, the hull by its bounds, the sums and the
  // representing shape of each hull recomputed from scratch.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0, 1);
  const auto lattice = [&](double lo, double hi) { return 0.1 * std::floor((lo + (hi - lo) * u(rng)) * 10); };
  for (int trial = 0; trial < 6; ++trial) {
    GroundTruth truth;
    std::vector<std::pair<V3, V3>> boxes;
    for (int k = 0; k < 5; ++k) {
      const V3 lo = hullmap::test::drawPoint([&] { return u(rng); }).cwiseProduct(V3(2, 2, 1));
      const V3 hi = lo + (V3::Constant(0.1) + 0.7 * hullmap::test::drawPoint([&] { return u(rng); }));
      boxes.emplace_back(lo, hi);
      truth.shapes.push_back(aabb(lo, hi));
    }
    std::vector<hulls::Obstacle> obstacles;
    std::vector<std::pair<V3, V3>> hull_boxes;
    for (int h = 0; h < 7; ++h) {
      const double lo_z = lattice(0, 1), lo_y = lattice(0, 2), lo_x = lattice(0, 2);  // as drawPoint
      const V3 lo(lo_x, lo_y, lo_z);
      const V3 hi = lo + hullmap::test::drawPoint([&] { return lattice(0.1, 1.0); }) + V3::Constant(0.1);
      obstacles.push_back(test::filledObstacle(lo, hi, h));
      hull_boxes.emplace_back(lo, hi);
    }
    std::vector<V3> points;
    std::vector<std::uint32_t> weights;
    for (int i = 0; i < 3000; ++i) {
      const auto& [lo, hi] = boxes[std::size_t(i) % boxes.size()];
      V3 p = lo + (hi - lo).cwiseProduct(hullmap::test::drawPoint([&] { return u(rng); }));
      const int axis = int(rng() % 3);
      p[axis] = (rng() % 2) ? lo[axis] : hi[axis];
      p += 0.08 * (2.0 * hullmap::test::drawPoint([&] { return u(rng); }) - V3::Ones());
      points.push_back(p);
      weights.push_back(1 + std::uint32_t(rng() % 4));
    }
    EvaluateParams params;
    params.segments = 0;
    params.volume_samples = 10;
    const Evaluation e = evaluate(obstacles, truth, points, weights, params);

    const auto distance = [](const V3& p, const V3& lo, const V3& hi) {
      double outside = 0, inside = -std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        const double gap = std::max(lo[a] - p[a], p[a] - hi[a]);  // > 0 outside along a
        if (gap > 0) outside += gap * gap;
        inside = std::max(inside, gap);
      }
      return outside > 0 ? std::sqrt(outside) : inside;
    };
    std::vector<double> near(boxes.size(), 0), in(boxes.size(), 0);
    std::vector<std::vector<double>> held(hull_boxes.size(), std::vector<double>(boxes.size(), 0));
    std::size_t owned = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      int owner = -1;
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t s = 0; s < boxes.size(); ++s) {
        const double d = std::abs(distance(points[i], boxes[s].first, boxes[s].second));
        if (d < best) {
          best = d;
          owner = int(s);
        }
      }
      if (best > params.surface_margin) continue;
      ++owned;
      near[std::size_t(owner)] += weights[i];
      bool inside = false;
      for (std::size_t h = 0; h < hull_boxes.size(); ++h) {
        const auto& [lo, hi] = hull_boxes[h];
        if ((points[i].array() >= lo.array() - 1e-9).all() && (points[i].array() <= hi.array() + 1e-9).all()) {
          inside = true;
          held[h][std::size_t(owner)] += weights[i];
        }
      }
      if (inside) in[std::size_t(owner)] += weights[i];
    }
    ASSERT_GT(owned, 1000u);
    std::vector<std::vector<std::pair<int, int>>> represents(boxes.size());
    std::size_t representing = 0;
    for (std::size_t h = 0; h < hull_boxes.size(); ++h) {
      int most = -1;
      for (std::size_t s = 0; s < boxes.size(); ++s)
        if (held[h][s] > 0 && (most < 0 || held[h][s] > held[h][std::size_t(most)])) most = int(s);
      if (most >= 0) {
        represents[std::size_t(most)].emplace_back(int(h), -1);
        ++representing;
      }
    }
    EXPECT_GE(representing, 3u);
    for (std::size_t s = 0; s < boxes.size(); ++s) {
      EXPECT_EQ(e.truth[s].points_near, near[s]) << "trial " << trial << " shape " << s;
      EXPECT_EQ(e.truth[s].points_inside, in[s]) << "trial " << trial << " shape " << s;
      EXPECT_EQ(e.truth[s].parts, represents[s]) << "trial " << trial << " shape " << s;
    }
  }
}

TEST(Evaluate, EachHullRepresentsOneTrueObstacle) {
  // A closed ring of four walls, each held exactly by one hull, and a crate standing against the
  // south wall with its own hull; a hull far away holds no point. Touching counts the neighbours at
  // the corners (3 per wall, 4 for the south wall with the crate on it); representing counts one
  // hull per obstacle, and the empty hull represents nothing.
  GroundTruth truth;
  const std::vector<std::pair<V3, V3>> walls{{V3(0, 0, 0), V3(4, 0.2, 1)},       // south
                                             {V3(0, 3.8, 0), V3(4, 4, 1)},       // north
                                             {V3(0, 0.2, 0), V3(0.2, 3.8, 1)},   // west
                                             {V3(3.8, 0.2, 0), V3(4, 3.8, 1)}};  // east
  const std::pair<V3, V3> crate{V3(1, 0.2, 0), V3(1.6, 0.6, 0.5)};
  std::vector<hulls::Obstacle> obstacles;
  std::vector<V3> points;
  for (const auto& [lo, hi] : walls) {
    truth.shapes.push_back(aabb(lo, hi));
    obstacles.push_back(test::filledObstacle(lo, hi, int(obstacles.size())));
    for (const V3& p : faceSamples(lo, hi, 0.1)) points.push_back(p);
  }
  truth.shapes.push_back(aabb(crate.first, crate.second));
  obstacles.push_back(test::filledObstacle(crate.first, crate.second, 4));
  for (const V3& p : faceSamples(crate.first, crate.second, 0.1)) points.push_back(p);
  obstacles.push_back(test::filledObstacle(V3(10, 10, 0), V3(10.5, 10.5, 0.5), 5));
  EvaluateParams params;
  params.segments = 0;
  const Evaluation e = evaluate(obstacles, truth, points, {}, params);
  ASSERT_EQ(e.truth.size(), 5u);
  for (std::size_t s = 0; s < 5; ++s) {
    ASSERT_EQ(e.truth[s].parts.size(), 1u) << s;
    EXPECT_EQ(e.truth[s].parts[0], std::make_pair(int(s), -1)) << s;
    EXPECT_EQ(e.truth[s].points_inside, e.truth[s].points_near) << s;
  }
  EXPECT_EQ(e.truth[0].parts_touching.size(), 4u);  // east, west, the crate and itself
  EXPECT_EQ(e.truth[1].parts_touching.size(), 3u);
  EXPECT_EQ(e.truth[2].parts_touching.size(), 3u);
  EXPECT_EQ(e.truth[3].parts_touching.size(), 3u);
  EXPECT_EQ(e.truth[4].parts_touching.size(), 2u);  // the crate's and the south wall's
  ASSERT_EQ(e.false_parts.size(), 1u);
  EXPECT_EQ(e.false_parts[0].obstacle, 5);
  const auto json = evaluationToJson(e, params);
  ASSERT_EQ(json["truth"][0]["parts"].size(), 1u);
  EXPECT_EQ(json["truth"][0]["parts"][0]["obstacle"], 0);
  EXPECT_EQ(json["truth"][0]["parts"][0]["part"], -1);
  EXPECT_EQ(json["truth"][0]["parts_touching"].size(), 4u);
}

}  // namespace
}  // namespace hullmap::sim
