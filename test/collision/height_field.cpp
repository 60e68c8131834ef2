// The ground's height field as an obstacle: the capsule against the solid under its triangles
// (oracle: each prism under a triangle of the grown lattice built here as a hull, the segment's
// distance to it by golden-section search, the first contact by bisection on that), a level field
// is the floor plane, and both checkers name the ground.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <octomap/OcTree.h>

#include "collision_oracle.hpp"
#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/core/height_field.hpp"

namespace hullmap::collision {
namespace {

using test::V3;

HeightField randomField(std::mt19937& rng, std::size_t nx, std::size_t ny, double step, double relief) {
  std::uniform_real_distribution<double> h(0.0, relief);
  HeightField f;
  f.origin = {-0.3, 0.2};
  f.step = step;
  f.nx = nx;
  f.ny = ny;
  for (std::size_t k = 0; k < nx * ny; ++k) f.heights.push_back(h(rng));
  return f;
}

/// The oracle's solid: one hull per triangle of the field's lattice grown by a ring of nodes
/// step * (nx + ny) beyond its span (level with the edge), down to as far below the lowest node.
std::vector<hulls::ConvexHull> prisms(const HeightField& f) {
  const double reach = f.step * double(f.nx + f.ny);
  std::vector<double> xs{f.origin.x() + 0.5 * f.step - reach}, ys{f.origin.y() + 0.5 * f.step - reach};
  for (std::size_t i = 0; i < f.nx; ++i) xs.push_back(f.origin.x() + (double(i) + 0.5) * f.step);
  for (std::size_t j = 0; j < f.ny; ++j) ys.push_back(f.origin.y() + (double(j) + 0.5) * f.step);
  xs.push_back(xs.back() + reach);
  ys.push_back(ys.back() + reach);
  double low = std::numeric_limits<double>::infinity();
  for (double z : f.heights) low = std::min(low, z);
  const double bottom = low - reach;
  const auto node = [&](std::size_t k, std::size_t l) {
    const std::size_t i = std::min(std::max<std::size_t>(k, 1), f.nx) - 1;
    const std::size_t j = std::min(std::max<std::size_t>(l, 1), f.ny) - 1;
    return V3(xs[k], ys[l], f.heights[j * f.nx + i]);
  };
  std::vector<hulls::ConvexHull> out;
  const auto prism = [&](const V3& p, const V3& q, const V3& r) {
    hulls::ConvexHull h;
    h.vertices = {p, q, r, V3(p.x(), p.y(), bottom), V3(q.x(), q.y(), bottom), V3(r.x(), r.y(), bottom)};
    // Counter-clockwise from above: top (0 1 2) faces up, bottom (3 5 4) down, the sides out.
    const bool ccw = (q - p).head<2>().x() * (r - p).head<2>().y() - (q - p).head<2>().y() * (r - p).head<2>().x() > 0;
    const int b = ccw ? 1 : 2, c = ccw ? 2 : 1;
    h.triangles = {{0, b, c}, {3, 3 + c, 3 + b}};
    const std::array<int, 3> ring{0, b, c};
    for (int e = 0; e < 3; ++e) {
      const int u = ring[e], v = ring[(e + 1) % 3];
      h.triangles.push_back({u, 3 + u, 3 + v});
      h.triangles.push_back({u, 3 + v, v});
    }
    out.push_back(h);
  };
  for (std::size_t l = 0; l + 1 < ys.size(); ++l)
    for (std::size_t k = 0; k + 1 < xs.size(); ++k) {
      prism(node(k, l), node(k + 1, l), node(k + 1, l + 1));
      prism(node(k, l), node(k + 1, l + 1), node(k, l + 1));
    }
  return out;
}

double oracleDistance(const V3& a, const V3& b, const std::vector<hulls::ConvexHull>& solid) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& h : solid) best = std::min(best, test::segmentHull(a, b, h));
  return best;
}

TEST(HeightFieldSurface, HeightIsLinearOnTheTrianglesAndLevelBeyondTheEdge) {
  HeightField f;
  f.origin = {0.0, 0.0};
  f.step = 2.0;
  f.nx = 2;
  f.ny = 2;
  f.heights = {0.0, 1.0, 2.0, 4.0};  // nodes at (1, 1), (3, 1), (1, 3), (3, 3)
  EXPECT_DOUBLE_EQ(f.height(1, 1), 0.0);
  EXPECT_DOUBLE_EQ(f.height(3, 3), 4.0);
  EXPECT_DOUBLE_EQ(f.height(2, 2), 2.0);  // the diagonal from (0, 0) to (1, 1)
  EXPECT_DOUBLE_EQ(f.height(3, 2), 2.5);  // below the diagonal: nodes (1, 1), (3, 1), (3, 3)
  EXPECT_DOUBLE_EQ(f.height(1, 2), 1.0);  // above it: nodes (1, 1), (1, 3), (3, 3)
  EXPECT_DOUBLE_EQ(f.height(-50, 1), 0.0);
  EXPECT_DOUBLE_EQ(f.height(2, 90), 3.0);
  EXPECT_DOUBLE_EQ(f.lowest(), 0.0);
  EXPECT_DOUBLE_EQ(f.highest(), 4.0);
}

TEST(HeightFieldSurface, CapsuleAgainstTheGroundMatchesTheOracle) {
  std::mt19937 rng(5);
  int collisions = 0, clear = 0;
  for (int field = 0; field < 6; ++field) {
    const HeightField f = randomField(rng, 2 + std::size_t(field % 3), 2 + std::size_t(field / 3), 1.0, 1.5);
    const Surface ground = Surface::heightField("ground", f);
    const auto solid = prisms(f);
    std::uniform_real_distribution<double> x(-1.0, double(f.nx) + 0.5), y(-0.5, double(f.ny) + 1.0), z(-0.5, 3.0);
    for (int trial = 0; trial < 25; ++trial) {
      const Segment s{V3(x(rng), y(rng), z(rng)), V3(x(rng), y(rng), z(rng))};
      const double r = std::array<double, 3>{0.0, 0.1, 0.5}[std::size_t(trial % 3)];
      const SegmentCheck c = checkSurface(s, r, ground);
      const double d = oracleDistance(s.a, s.b, solid);
      if (std::abs(d - r) < 1e-7) continue;  // at the radius: either answer is right
      ASSERT_EQ(c.collides, d <= r) << "field " << field << " trial " << trial << ": distance " << d;
      if (!c.collides) {
        ++clear;
        EXPECT_NEAR(c.clearance, d - r, 1e-7);
        EXPECT_TRUE(c.surface.empty());
        continue;
      }
      ++collisions;
      EXPECT_EQ(c.surface, "ground");
      EXPECT_EQ(c.clearance, 0.0);
      const auto touches = [&](double t) { return oracleDistance(s.a, s.a + t * (s.b - s.a), solid) <= r; };
      double lo = 0.0, hi = 1.0;
      if (touches(0.0)) hi = 0.0;
      while (hi - lo > 1e-9) {
        const double mid = 0.5 * (lo + hi);
        (touches(mid) ? hi : lo) = mid;
      }
      const double tolerance = std::max(1e-3, kContactTolerance / (s.b - s.a).norm());
      EXPECT_GE(c.t, lo - 1e-7) << "field " << field << " trial " << trial;
      EXPECT_LE(c.t, hi + tolerance + 1e-7) << "field " << field << " trial " << trial;
    }
  }
  EXPECT_GT(collisions, 20);
  EXPECT_GT(clear, 20);
}

TEST(HeightFieldSurface, ALevelFieldIsTheFloorPlane) {
  HeightField f;
  f.origin = {0.0, 0.0};
  f.step = 2.0;
  f.nx = 5;
  f.ny = 4;
  f.heights.assign(20, 0.25);
  const Surface ground = Surface::heightField("ground", f), floor = Surface::plane("floor", V3::UnitZ(), 0.25);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> x(-5.0, 15.0), z(-1.0, 3.0), radius(0.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const Segment s{V3(x(rng), x(rng), z(rng)), V3(x(rng), x(rng), z(rng))};
    const double r = radius(rng);
    const SegmentCheck g = checkSurface(s, r, ground, 1e-6), p = checkSurface(s, r, floor);
    ASSERT_EQ(g.collides, p.collides) << "trial " << trial;
    if (p.collides) {
      EXPECT_GE(g.t, p.t - 1e-9);
      EXPECT_LE(g.t, p.t + std::max(1e-3, 1e-6 / (s.b - s.a).norm()) + 1e-9);
    } else {
      EXPECT_NEAR(g.clearance, p.clearance, 1e-8);
    }
  }
}

TEST(HeightFieldSurface, BothCheckersTakeTheGroundAsAnObstacle) {
  std::mt19937 rng(3);
  const HeightField f = randomField(rng, 6, 6, 0.5, 0.4);
  const std::vector<Surface> surfaces{Surface::heightField("ground", f)};
  const HullChecker hulls({}, surfaces);
  octomap::OcTree tree(0.1);
  tree.updateNode(octomap::point3d(20, 20, 20), true);  // far from every segment below
  const OctreeChecker voxels(tree, surfaces);
  // Down through the ground: a collision with it, at the height over the surface less the radius.
  const Segment down{V3(1.3, 1.1, 2.0), V3(1.3, 1.1, -1.0)};
  const double over = 2.0 - f.height(1.3, 1.1);
  for (const SegmentCheck& c : {hulls.check(down, 0.2), voxels.check(down, 0.2)}) {
    ASSERT_TRUE(c.collides);
    EXPECT_EQ(c.surface, "ground");
    EXPECT_EQ(c.obstacle, -1);
    EXPECT_LE(c.t * 3.0, over - 0.2 + 1e-9);  // the slope may bring the contact earlier, never later
  }
  // Level, 2 m over the highest node: clear, and the clearance is at most the height over it.
  const Segment over_it{V3(0.0, 0.0, 2.4), V3(3.0, 3.0, 2.4)};
  const SegmentCheck c = hulls.check(over_it, 0.1);
  EXPECT_FALSE(c.collides);
  EXPECT_LE(c.clearance, 2.4 - f.highest() + 0.4 - 0.1);
  EXPECT_GE(c.clearance, 2.4 - f.highest() - 0.1 - 1e-9);
}

TEST(HeightFieldSurface, AnInvalidFieldIsRefused) {
  HeightField f;
  f.nx = 2;
  f.ny = 2;
  f.heights = {0.0, 1.0, NAN, 0.0};
  EXPECT_THROW(HullChecker({}, {Surface::heightField("ground", f)}), Error);
  f.heights = {0.0, 1.0, 0.0};
  EXPECT_THROW(checkSurface({V3::Zero(), V3::Ones()}, 0.1, Surface::heightField("ground", f)), Error);
  f.heights = {0.0, 1.0, 0.0, 0.0};
  f.step = 0.0;
  EXPECT_THROW(HullChecker({}, {Surface::heightField("ground", f)}), Error);
}

}  // namespace
}  // namespace hullmap::collision
