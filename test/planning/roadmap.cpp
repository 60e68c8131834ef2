#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/convex_hull_2d.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/planning/path_planner.hpp"
#include "hullmap/planning/roadmap.hpp"
#include "planning_support.hpp"

namespace hullmap {
namespace {

using Eigen::Vector2d;
using planning::Roadmap;
using planning::RoadmapParams;

/// Random convex polygons, one per cell of a grid with a gap between cells (so they are disjoint).
std::vector<hulls::Obstacle> randomPolygons(std::mt19937& rng, int per_side, double cell) {
  std::uniform_real_distribution<double> u(0.1 * cell, 0.9 * cell);
  std::uniform_int_distribution<int> count(3, 9);
  std::bernoulli_distribution present(0.8);
  std::vector<hulls::Obstacle> out;
  for (int i = 0; i < per_side; ++i)
    for (int j = 0; j < per_side; ++j) {
      if (!present(rng)) continue;
      std::vector<Vector2d> pts;
      for (int k = count(rng); k > 0; --k) pts.emplace_back(i * cell + u(rng), j * cell + u(rng));
      auto hull = hullmap::core::convexHull2d(pts);
      if (hull.size() < 3) continue;
      out.push_back(test::prism(static_cast<int>(out.size()) + 100, hull, 0.0, 1.0));
    }
  return out;
}

/// Brute-force distance from p to the region covered by the footprints (those of an obstacle's
/// parts when it has parts): 0 inside one, else to the nearest footprint or bounds edge.
double nearestSite(const std::vector<hulls::Obstacle>& obstacles, const Roadmap& map, const Vector2d& p) {
  double best = std::min({p.x() - map.bounds.x0, map.bounds.x1 - p.x(), p.y() - map.bounds.y0, map.bounds.y1 - p.y()});
  auto visit = [&](const std::vector<Vector2d>& poly) {
    bool inside = true;  // counter-clockwise convex: strictly left of every edge
    for (std::size_t k = 0; k < poly.size(); ++k) {
      planning::SiteRef s;
      s.a = poly[k];
      s.b = poly[(k + 1) % poly.size()];
      best = std::min(best, planning::siteDistance(s, p));
      const Vector2d e = s.b - s.a, q = p - s.a;
      inside = inside && e.x() * q.y() - e.y() * q.x() > 0;
    }
    if (inside) best = 0;
  };
  for (const auto& o : obstacles) {
    if (o.parts.empty()) visit(o.footprint.polygon);
    for (const auto& part : o.parts) visit(part.footprint.polygon);
  }
  return best;
}

/// Axis-aligned rectangle [x0, x1] x [y0, y1], counter-clockwise.
std::vector<Vector2d> rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

/// The walls of a room [0, 6]^2, 0.2 thick, as ONE obstacle (id 1) whose four convex parts touch
/// along their ends (its whole hull and footprint cover the room), and a box (id 2) in the middle.
std::vector<hulls::Obstacle> ringRoom() {
  auto ring = test::prism(1, rect(-0.2, -0.2, 6.2, 6.2), 0, 2);
  for (const auto& r : {rect(-0.2, -0.2, 6.2, 0), rect(-0.2, 6, 6.2, 6.2), rect(-0.2, 0, 0, 6), rect(6, 0, 6.2, 6)}) {
    const auto wall = test::prism(1, r, 0, 2);
    hulls::ObstaclePart part;
    part.hull = wall.hull;
    part.footprint = wall.footprint;
    part.aabb_min = wall.aabb_min;
    part.aabb_max = wall.aabb_max;
    ring.parts.push_back(part);
  }
  return {ring, test::prism(2, rect(2.5, 2.5, 3.5, 3.5), 0, 2)};
}

TEST(Roadmap, EdgesAreEquidistantToTheirSitesAndNoObstacleIsNearer) {
  for (const unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    std::mt19937 rng(seed);
    const auto obstacles = randomPolygons(rng, 5, 2.0);
    RoadmapParams params;
    params.tolerance = 1e-3;
    const Roadmap map = planning::buildRoadmap(obstacles, params);
    ASSERT_GT(map.edges.size(), obstacles.size()) << "seed " << seed;
    std::size_t checked = 0;
    for (const auto& e : map.edges) {
      ASSERT_GE(e.polyline.size(), 2u);
      EXPECT_NE(e.site_a.obstacle, e.site_b.obstacle) << "edge between two sites of one obstacle";
      double sampled_min = 1e300;
      for (std::size_t k = 0; k < e.polyline.size(); ++k) {
        const Vector2d& p = e.polyline[k];
        const double da = planning::siteDistance(e.site_a, p), db = planning::siteDistance(e.site_b, p);
        EXPECT_NEAR(da, db, 1e-6) << "seed " << seed << " point " << p.transpose();
        EXPECT_GE(nearestSite(obstacles, map, p), std::min(da, db) - 1e-6)
            << "seed " << seed << ": a site nearer than the edge's own at " << p.transpose();
        // Chords lie within the tolerance of the arc, so their points are equidistant within it.
        if (k > 0) {
          const Vector2d& q = e.polyline[k - 1];
          const int steps = std::max(2, static_cast<int>(std::ceil((p - q).norm() / 1e-3)));
          for (int i = 0; i <= steps; ++i) {
            const Vector2d m = q + (p - q) * (static_cast<double>(i) / steps);
            const double ma = planning::siteDistance(e.site_a, m), mb = planning::siteDistance(e.site_b, m);
            EXPECT_NEAR(ma, mb, 2 * params.tolerance + 1e-6);
            sampled_min = std::min(sampled_min, nearestSite(obstacles, map, m));
          }
        }
        ++checked;
      }
      // Brute-force clearance oracle: every point of the arc is within the tolerance of a chord
      // point sampled 1 mm apart (distance is 1-Lipschitz), so the exact clearance is within
      // tolerance + 0.5 mm of the sampled minimum of the nearest-site distance.
      EXPECT_NEAR(e.clearance, sampled_min, params.tolerance + 0.5e-3 + 1e-9) << "seed " << seed;
    }
    EXPECT_GT(checked, 100u);
  }
}

TEST(Roadmap, MinClearanceDropsNarrowEdgesAndKeepsWideOnes) {
  // Two unit squares 1 m apart in a 10 m box: the passage between them has clearance 0.5.
  const auto a = test::prism(1, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 0, 1);
  const auto b = test::prism(2, {{2, 0}, {3, 0}, {3, 1}, {2, 1}}, 0, 1);
  RoadmapParams params;
  params.bounds = planning::Bounds2d{-4, -4, 7, 5};
  const Roadmap all = planning::buildRoadmap({a, b}, params);
  // A chord on x = 1.5 across y = 0.5 (the bisector of the facing sides).
  auto crossesGap = [](const planning::RoadmapEdge& e) {
    for (std::size_t k = 1; k < e.polyline.size(); ++k) {
      const Vector2d& p = e.polyline[k - 1];
      const Vector2d& q = e.polyline[k];
      if (std::abs(p.x() - 1.5) < 1e-9 && std::abs(q.x() - 1.5) < 1e-9 && (p.y() - 0.5) * (q.y() - 0.5) < 0)
        return true;
    }
    return false;
  };
  bool passage = false;
  for (const auto& e : all.edges) passage = passage || crossesGap(e);
  EXPECT_TRUE(passage) << "no roadmap edge runs through the gap at x = 1.5";
  params.min_clearance = 0.6;
  const Roadmap wide = planning::buildRoadmap({a, b}, params);
  EXPECT_LT(wide.edges.size(), all.edges.size());
  for (const auto& e : wide.edges) {
    EXPECT_GE(e.clearance, 0.6);
    EXPECT_FALSE(crossesGap(e));
  }
}

TEST(Roadmap, BandSelectsObstaclesAndJsonIsTheDocumentedGraph) {
  const auto low = test::prism(1, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 0, 1);
  const auto high = test::prism(2, {{3, 0}, {4, 0}, {4, 1}, {3, 1}}, 2, 3);
  RoadmapParams params;
  params.z0 = 0.2;
  params.z1 = 0.8;
  const Roadmap map = planning::buildRoadmap({low, high}, params);
  ASSERT_EQ(map.obstacle_groups, std::vector<std::vector<int>>{{1}});
  EXPECT_DOUBLE_EQ(map.bounds.x1, 2.0);  // low's footprint grown by the 1 m margin
  const auto j = nlohmann::json::parse(planning::roadmapJson(map));
  EXPECT_EQ(j["format"], "hullmap-roadmap/1");
  ASSERT_EQ(j["edges"].size(), map.edges.size());
  ASSERT_EQ(j["nodes"].size(), map.nodes.size());
  for (const auto& e : j["edges"]) {
    const auto& first = j["nodes"][e["from"].get<std::size_t>()];
    EXPECT_EQ(e["polyline"].front(), first);
    EXPECT_GE(e["clearance"].get<double>(), 0.0);
  }
}

/// Connected components of the roadmap graph.
std::size_t components(const Roadmap& map) {
  std::vector<int> parent(map.nodes.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  std::function<int(int)> find = [&](int i) { return parent[i] == i ? i : parent[i] = find(parent[i]); };
  for (const auto& e : map.edges) parent[find(e.from)] = find(e.to);
  std::size_t roots = 0;
  for (std::size_t i = 0; i < parent.size(); ++i) roots += find(static_cast<int>(i)) == static_cast<int>(i);
  return roots;
}

TEST(Roadmap, TouchingAndOverlappingFootprintsKeepTheRoadmapConnected) {
  // Fragments of one voxelized object: edges on the same lines, overlapping in part, one footprint
  // inside another (CGAL splits such edges into pieces whose ends come from different obstacles),
  // and separate obstacles around them. The free space is connected, so must the roadmap be.
  const std::vector<hulls::Obstacle> obstacles{
      test::prism(1, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 0, 1),
      test::prism(2, {{0.5, 1}, {1.5, 1}, {1.5, 2}, {0.5, 2}}, 0, 1),
      test::prism(3, {{0.2, 0.5}, {0.6, 0.5}, {0.6, 1}, {0.2, 1}}, 0, 1),
      test::prism(4, {{1, 0.25}, {1.75, 0.25}, {1.75, 0.75}, {1, 0.75}}, 0, 1),
      test::prism(5, {{3, 0}, {4, 0}, {4, 1}, {3, 1}}, 0, 1),
      test::prism(6, {{-2, 2}, {-1, 2}, {-1.5, 3}}, 0, 1),
  };
  const Roadmap map = planning::buildRoadmap(obstacles, {});
  ASSERT_EQ(map.footprints.size(), 3u);  // 1-4 meet: one hull
  EXPECT_EQ(map.obstacle_groups[0], (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(components(map), 1u);
  for (const auto& e : map.edges)
    for (const auto& p : e.polyline) {
      const double da = planning::siteDistance(e.site_a, p), db = planning::siteDistance(e.site_b, p);
      EXPECT_NEAR(da, db, 1e-6);
      EXPECT_GE(nearestSite(obstacles, map, p), std::min(da, db) - 1e-6);
    }
  std::mt19937 rng(7);
  for (int round = 0; round < 5; ++round)
    EXPECT_EQ(components(planning::buildRoadmap(randomPolygons(rng, 6, 1.5), {})), 1u);
}

TEST(Roadmap, AVertexOfTwoParallelSegmentsAndAPointKeepsTheRoadmapConnected) {
  // The Voronoi vertex equidistant to the bounds' side x = 5.1, the side x = 1.2 of one footprint and
  // the corner (3.1, 0.5) of another (x = 3.15, y = 0.5 - sqrt(1.95^2 - 0.05^2)): its construction in
  // double divides by zero (parallel segments) and gave NaN; the face was dropped and with it the
  // only link between the roadmap's two halves on a built scene (CliPlan found no path).
  const std::vector<hulls::Obstacle> obstacles{
      test::prism(5, rect(1.0, -1.45, 1.2, -1.25), 0, 1),
      test::prism(7, rect(3.05, 0.5, 3.1, 0.6), 0, 1),
  };
  RoadmapParams params;
  params.bounds = planning::Bounds2d{-5.1, -5.1, 5.1, 5.1};
  const Roadmap map = planning::buildRoadmap(obstacles, params);
  const Vector2d expected(3.15, 0.5 - std::sqrt(1.95 * 1.95 - 0.05 * 0.05));
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& n : map.nodes) {
    ASSERT_TRUE(n.position.allFinite());
    nearest = std::min(nearest, (n.position - expected).norm());
  }
  EXPECT_LT(nearest, 1e-6);
  EXPECT_EQ(components(map), 1u);
}

TEST(Roadmap, ARingOfWallPartsLeavesTheRoomInsideFree) {
  const auto obstacles = ringRoom();
  const Roadmap map = planning::buildRoadmap(obstacles, {});
  // The walls' parts meet: their exact union is one footprint with the room as its hole.
  ASSERT_EQ(map.footprints.size(), 2u);
  ASSERT_EQ(map.holes.size(), 2u);
  std::size_t with_hole = 0;
  for (std::size_t i = 0; i < map.footprints.size(); ++i) with_hole += map.holes[i].size();
  EXPECT_EQ(with_hole, 1u);
  const auto json = nlohmann::json::parse(planning::roadmapJson(map));
  std::size_t json_holes = 0;
  for (const auto& o : json.at("obstacles")) json_holes += o.value("holes", nlohmann::json::array()).size();
  EXPECT_EQ(json_holes, 1u);
  std::size_t inside = 0;
  for (const auto& e : map.edges) {
    bool in_room = true;
    for (const auto& p : e.polyline) {
      in_room = in_room && p.x() > 0 && p.x() < 6 && p.y() > 0 && p.y() < 6;
      const double da = planning::siteDistance(e.site_a, p), db = planning::siteDistance(e.site_b, p);
      EXPECT_NEAR(da, db, 1e-6) << p.transpose();
      EXPECT_GE(nearestSite(obstacles, map, p), std::min(da, db) - 1e-6) << "a site nearer at " << p.transpose();
      EXPECT_GT(nearestSite(obstacles, map, p), 0) << "edge inside an obstacle at " << p.transpose();
    }
    inside += in_room;
  }
  EXPECT_GE(inside, 4u) << "no roadmap around the box inside the room";

  // A flight from one side of the box to the other, inside the room, which the hull checker accepts.
  planning::PlanRequest request;
  request.start = {1, 3, 1};
  request.goal = {5, 3, 1};
  request.radius = 0.3;
  const auto result = planning::planPath(obstacles, request);
  ASSERT_TRUE(result.path) << result.blocked;
  for (const auto& p : *result.path) {
    EXPECT_GT(p.x(), 0);
    EXPECT_LT(p.x(), 6);
    EXPECT_GT(p.y(), 0);
    EXPECT_LT(p.y(), 6);
  }
  const collision::HullChecker checker(obstacles);
  EXPECT_FALSE(checker.checkPath(*result.path, request.radius).first_colliding_segment);
}

TEST(Roadmap, NodesAndEdgesComeInACanonicalOrder) {
  // Nodes by position (x, then y), edges by their nodes with from < to, each polyline running from
  // its `from` node to its `to` node: the numbering does not follow the SDG's face order, which
  // follows heap addresses where sites are co-circular (a grid of equal boxes has plenty).
  std::vector<hulls::Obstacle> obstacles;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      obstacles.push_back(test::prism(4 * i + j, rect(2.0 * i, 2.0 * j, 2.0 * i + 1, 2.0 * j + 1), 0, 1));
  const Roadmap map = planning::buildRoadmap(obstacles, {});
  ASSERT_GT(map.edges.size(), 10u);
  for (std::size_t k = 1; k < map.nodes.size(); ++k) {
    const Vector2d& p = map.nodes[k - 1].position;
    const Vector2d& q = map.nodes[k].position;
    EXPECT_TRUE(p.x() < q.x() || (p.x() == q.x() && p.y() < q.y())) << "node " << k;
  }
  for (std::size_t k = 0; k < map.edges.size(); ++k) {
    const auto& e = map.edges[k];
    EXPECT_LT(e.from, e.to) << "edge " << k;
    EXPECT_EQ(e.polyline.front(), map.nodes[e.from].position) << "edge " << k;
    EXPECT_EQ(e.polyline.back(), map.nodes[e.to].position) << "edge " << k;
    if (k > 0) {
      const auto& d = map.edges[k - 1];
      EXPECT_LE(std::make_pair(d.from, d.to), std::make_pair(e.from, e.to)) << "edge " << k;
    }
  }
}

TEST(Roadmap, RejectsBadParameters) {
  const auto a = test::prism(1, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 0, 1);
  RoadmapParams params;
  params.tolerance = 0;
  EXPECT_EQ(test::refusedParameter([&] { planning::buildRoadmap({a}, params); }), "tolerance");
  params = {};
  params.bounds = planning::Bounds2d{1, 0, 0, 1};
  EXPECT_EQ(test::refusedParameter([&] { planning::buildRoadmap({a}, params); }), "bounds");
  params = {};
  params.min_clearance = -1;
  EXPECT_EQ(test::refusedParameter([&] { planning::buildRoadmap({a}, params); }), "min_clearance");
  auto flat = a;
  flat.footprint.polygon.resize(2);
  EXPECT_THROW(planning::buildRoadmap({flat}, {}), Error);
}

}  // namespace
}  // namespace hullmap
