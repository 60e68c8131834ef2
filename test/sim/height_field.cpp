// The height field (a terrain's truth): its signed distance against the distance to every one of its
// triangles, its height against the triangle under the point, bad "heightfield" JSON refused, and
// evaluate with one: segments above the ground where they are, hulls far above it false.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "evaluate_fixtures.hpp"
#include "hullmap/collision/convex_distance.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/sim/evaluate.hpp"
#include "hullmap/sim/ground_truth.hpp"
#include "test_support.hpp"

namespace hullmap::sim {
namespace {

using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

// A rough terrain: random heights in [-1, 1] with a spike and a pit, step 0.7.
TruthShape roughTerrain(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  HeightGrid g;
  g.origin = V2(-3.0, 2.0);
  g.step = 0.7;
  g.nx = 13;
  g.ny = 9;
  for (std::size_t k = 0; k < g.nx * g.ny; ++k) g.heights.push_back(u(rng));
  g.heights[5 * g.nx + 6] = 4.0;
  g.heights[2 * g.nx + 3] = -3.5;
  return TruthShape::heightField(g, "ground");
}

// The grid's triangles as the header states them: per cell, (i,j)(i+1,j)(i+1,j+1) and
// (i,j)(i+1,j+1)(i,j+1).
std::vector<std::array<V3, 3>> triangles(const HeightGrid& g) {
  std::vector<std::array<V3, 3>> out;
  const auto node = [&](std::size_t i, std::size_t j) {
    return V3(g.origin.x() + g.step * double(i), g.origin.y() + g.step * double(j), g.heights[j * g.nx + i]);
  };
  for (std::size_t j = 0; j + 1 < g.ny; ++j)
    for (std::size_t i = 0; i + 1 < g.nx; ++i) {
      out.push_back({node(i, j), node(i + 1, j), node(i + 1, j + 1)});
      out.push_back({node(i, j), node(i + 1, j + 1), node(i, j + 1)});
    }
  return out;
}

// The height of the triangle whose (x, y) projection holds q, by barycentric coordinates; NaN when
// none does.
double oracleHeight(const std::vector<std::array<V3, 3>>& tris, const V2& q) {
  for (const auto& t : tris) {
    const V2 a = t[0].head<2>(), b = t[1].head<2>(), c = t[2].head<2>();
    const double det = (b - a).x() * (c - a).y() - (c - a).x() * (b - a).y();
    const double l1 = ((q - a).x() * (c - a).y() - (c - a).x() * (q - a).y()) / det;
    const double l2 = ((b - a).x() * (q - a).y() - (q - a).x() * (b - a).y()) / det;
    if (l1 >= -1e-12 && l2 >= -1e-12 && l1 + l2 <= 1.0 + 1e-12)
      return (1.0 - l1 - l2) * t[0].z() + l1 * t[1].z() + l2 * t[2].z();
  }
  return std::numeric_limits<double>::quiet_NaN();
}

TEST(HeightFieldTruth, SignedDistanceIsTheDistanceToTheNearestTriangle) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const TruthShape terrain = roughTerrain(seed);
    ASSERT_EQ(terrain.shape, TruthShape::Shape::kHeightField);
    EXPECT_TRUE(terrain.surface);
    const auto tris = triangles(terrain.grid);
    std::mt19937_64 rng(seed + 10);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const V3 lo = terrain.aabb_min - V3(3, 3, 3), hi = terrain.aabb_max + V3(3, 3, 3);
    for (int k = 0; k < 2000; ++k) {
      V3 p = lo + (hi - lo).cwiseProduct(V3(u(rng), u(rng), u(rng)));
      if (k % 4 == 0) p.z() = oracleHeight(tris, p.head<2>()) + 0.05 * (u(rng) - 0.5);  // near the surface
      if (!std::isfinite(p.z())) p.z() = 0.3;
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& t : tris) nearest = std::min(nearest, collision::pointTriangleDistance(p, t[0], t[1], t[2]));
      const double h = oracleHeight(tris, p.head<2>());
      const double oracle = std::isfinite(h) && p.z() < h ? -nearest : nearest;
      ASSERT_NEAR(terrain.signedDistance(p), oracle, 1e-9) << "seed " << seed << " at " << p.transpose();
    }
    // Far away, and exactly on the nodes.
    for (const V3& p : {V3(1e4, -3e4, 50.0), V3(-2.0, 5.0, 1e3), V3(-2.0, 5.0, -1e3)}) {
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& t : tris) nearest = std::min(nearest, collision::pointTriangleDistance(p, t[0], t[1], t[2]));
      EXPECT_NEAR(std::abs(terrain.signedDistance(p)), nearest, 1e-9 * std::max(1.0, nearest)) << p.transpose();
    }
    EXPECT_LT(terrain.signedDistance(V3(-2.0, 5.0, -1e3)), 0.0);
    for (const auto& t : tris)
      for (const V3& v : t) EXPECT_NEAR(terrain.signedDistance(v), 0.0, 1e-12);
  }
}

TEST(HeightFieldTruth, HeightIsThatOfTheTriangleUnderThePoint) {
  const TruthShape terrain = roughTerrain(4);
  const HeightGrid& g = terrain.grid;
  const auto tris = triangles(g);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.05, 1.05);
  std::size_t outside = 0;
  for (int k = 0; k < 3000; ++k) {
    const V2 q = g.origin + (g.corner() - g.origin).cwiseProduct(V2(u(rng), u(rng)));
    const std::optional<double> h = g.heightAt(q);
    const double oracle = oracleHeight(tris, q);
    ASSERT_EQ(h.has_value(), std::isfinite(oracle)) << q.transpose();
    if (h)
      EXPECT_NEAR(*h, oracle, 1e-12) << q.transpose();
    else
      ++outside;
  }
  EXPECT_GT(outside, 100u);
  EXPECT_EQ(terrain.aabb_min, V3(-3.0, 2.0, -3.5));
  EXPECT_EQ(terrain.aabb_max.z(), 4.0);
  EXPECT_NEAR(terrain.aabb_max.x(), -3.0 + 12 * 0.7, 1e-12);
}

TEST(HeightFieldTruth, BadGridsAreRefused) {
  HeightGrid g;
  g.nx = 3;
  g.ny = 2;
  g.heights = {0, 0, 0, 0, 0};
  EXPECT_THROW(TruthShape::heightField(g), Error);
  g.heights.push_back(std::nan(""));
  EXPECT_THROW(TruthShape::heightField(g), Error);
  g.heights.back() = 1.0;
  g.step = 0.0;
  EXPECT_THROW(TruthShape::heightField(g), Error);
  g.step = 2.0;
  EXPECT_NO_THROW(TruthShape::heightField(g));
  g.nx = 1;
  g.ny = 6;
  EXPECT_THROW(TruthShape::heightField(g), Error);
}

TEST(HeightFieldJson, BadHeightFieldsAreRefusedNamingTheField) {
  const auto dir = test::freshDir("heightfield_json");
  const std::string good = R"("shape": "heightfield", "kind": "ground", "origin": [0, 0], "step": 1)";
  const std::pair<std::string, std::string> cases[] = {
      {R"("shape": "heightfield", "step": 1, "size": [2, 2], "heights": [0, 0, 0, 0])",
       "obstacles[0]: missing \"origin\""},
      {R"("shape": "heightfield", "origin": [0], "step": 1, "size": [2, 2], "heights": [0, 0, 0, 0])",
       "obstacles[0].origin: expected [x, y]"},
      {R"("shape": "heightfield", "origin": [0, 0], "step": 0, "size": [2, 2], "heights": [0, 0, 0, 0])",
       "obstacles[0].step: expected a finite number > 0"},
      {R"("shape": "heightfield", "origin": [0, 0], "step": -1, "size": [2, 2], "heights": [0, 0, 0, 0])",
       "obstacles[0].step"},
      {good + R"(, "size": [1, 4], "heights": [0, 0, 0, 0])", "obstacles[0].size: expected [nx, ny]"},
      {good + R"(, "size": [2.5, 2], "heights": [0, 0, 0, 0])", "obstacles[0].size"},
      {good + R"(, "size": [-2, 2], "heights": [0, 0, 0, 0])", "obstacles[0].size"},
      {good + R"(, "size": [2, 3], "heights": [0, 0, 0, 0])",
       "obstacles[0].heights: expected nx * ny = 2 * 3 numbers, got 4"},
      {good + R"(, "size": [2, 2], "heights": [0, 0, "x", 0])", "obstacles[0].heights[2]: expected a finite number"},
      {good + R"(, "size": [2, 2], "heights": 4)", "obstacles[0].heights: expected an array"},
      {good + R"(, "size": [2, 2])", "obstacles[0]: missing \"heights\""},
  };
  for (const auto& [body, expected] : cases) {
    const auto path = dir / "truth.json";
    test::writeText(path, R"({"obstacles": [{)" + body + "}]}");
    try {
      readGroundTruth(path.string());
      ADD_FAILURE() << "accepted: " << body;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path.string() + ": ", 0), 0u) << what;
      EXPECT_NE(what.find(expected), std::string::npos) << what << "\n  expected: " << expected;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  // The good one reads, with its kind; without a kind, the shape's name.
  test::writeText(dir / "truth.json", R"({"obstacles": [{)" + good + R"(, "size": [2, 2], "heights": [0, 1, 2, 3]},
      {"shape": "heightfield", "origin": [0, 0], "step": 1, "size": [2, 2], "heights": [0, 1, 2, 3]}]})");
  const GroundTruth truth = readGroundTruth((dir / "truth.json").string());
  ASSERT_EQ(truth.shapes.size(), 2u);
  EXPECT_EQ(truth.shapes[0].label, "ground 0");
  EXPECT_EQ(truth.shapes[1].label, "heightfield 1");
  EXPECT_TRUE(truth.shapes[1].surface);
  EXPECT_NEAR(*truth.shapes[0].grid.heightAt(V2(0.5, 0.25)), 0.5 * 1 + 0.25 * (3 - 1), 1e-12);
}

// A terrain rising 0.1 m per metre along x with a 1.5 m ridge across it at y = 5.
TruthShape ridgedSlope() {
  HeightGrid g;
  g.nx = g.ny = 11;
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i) g.heights.push_back(0.1 * double(i) + (j == 5 ? 1.5 : 0.0));
  return TruthShape::heightField(g, "ground");
}

TEST(Evaluate, SegmentsStayAboveAHeightFieldWhereTheyAre) {
  // Above the ground at each endpoint's (x, y), not above its highest point (no segment would fit
  // in the truth's box) nor below its lowest (as a ceiling). The deep ones (through a box standing
  // in the ground, or the ridge) are all missed without hulls, and their ends are listed.
  GroundTruth truth;
  truth.add(ridgedSlope());
  truth.add(TruthShape::box(V3(5, 2, 0.8), V3(2, 2, 2)));
  const HeightGrid& g = truth.shapes[0].grid;
  for (const SegmentEnds ends : {SegmentEnds::kFree, SegmentEnds::kInTruthBox}) {
    EvaluateParams params;
    params.segments = 4000;
    params.ends = ends;
    const Evaluation e = evaluate({}, truth, {}, {}, params);
    EXPECT_EQ(e.segments, 4000u);
    // Free ends keep radius + clear_margin from everything: few of their segments are deep.
    EXPECT_GT(e.deep, ends == SegmentEnds::kFree ? 2u : 40u);
    EXPECT_GT(e.clear, 3000u);
    EXPECT_EQ(e.missed, e.deep);  // no hull: every deep segment is missed
    ASSERT_EQ(e.missed_segments.size(), e.missed);
    for (const MissedSegment& m : e.missed_segments) {
      for (const V3& p : {m.from, m.to}) {
        const Eigen::Vector2d xy = p.head<2>().cwiseMax(g.origin).cwiseMin(g.corner());
        EXPECT_GE(p.z(), *g.heightAt(xy) + params.radius + params.clear_margin - 1e-9) << p.transpose();
      }
    }
  }
}

TEST(Evaluate, AHeightFieldOwnsItsPointsAndFlagsHullsFarAboveIt) {
  GroundTruth truth;
  truth.add(ridgedSlope());
  const HeightGrid& g = truth.shapes[0].grid;
  std::vector<V3> points;
  for (double x = 0.25; x < 10; x += 0.5) points.emplace_back(x, 2.0, *g.heightAt({x, 2.0}));
  // One hull 2 m above the ground's highest point under it, one through the ground.
  const std::vector<hulls::Obstacle> obstacles{test::filledObstacle(V3(1, 1, 2.2), V3(2, 2, 3.2), 0),
                                               test::filledObstacle(V3(6, 1, 0.3), V3(7, 2, 1.3), 1)};
  EvaluateParams params;
  params.segments = 0;
  const Evaluation e = evaluate(obstacles, truth, points, {}, params);
  ASSERT_EQ(e.truth.size(), 1u);
  EXPECT_TRUE(e.truth[0].surface);
  EXPECT_EQ(e.truth[0].points_near, double(points.size()));
  ASSERT_EQ(e.false_parts.size(), 1u);
  EXPECT_EQ(e.false_parts[0].obstacle, 0);
  // Its nearest points: the bottom corners on the high side, (1.95, y, 2.25) over ground at 0.195.
  EXPECT_GT(e.false_parts[0].distance, 1.9);
  EXPECT_LT(e.false_parts[0].distance, 2.1);
}

}  // namespace
}  // namespace hullmap::sim
