// Exact segment-polytope distance: the library's certified GJK and its brute force against an
// independent oracle (test/support/collision_oracle.hpp), random, grazing and end-point cases; and FCL's
// own capsule-convex answers against the same oracle.
#include <gtest/gtest.h>

#include <array>

#include "collision_oracle.hpp"
#include "distance_fixtures.hpp"
#include "hullmap/collision/convex_distance.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::collision {
namespace {

TEST(ConvexDistance, MatchesOracleOnRandomSegments) {
  std::mt19937 rng(1);
  const auto hulls = randomHulls(rng, 40);
  int touching = 0;
  for (const auto& hull : hulls) {
    const auto p = ConvexPolytope::fromHull(hull, "test");
    for (int i = 0; i < 150; ++i) {
      const V3 a = randomPoint(rng, 1.5);
      const V3 b = (i % 5 == 0) ? a : (i % 3 == 0 ? a + randomPoint(rng, 0.2) : randomPoint(rng, 1.5));
      const double expected = test::segmentHull(a, b, hull);
      touching += expected == 0;
      EXPECT_NEAR(segmentPolytopeDistance(a, b, p), expected, 1e-9) << "segment " << i;
      EXPECT_NEAR(segmentPolytopeDistanceBruteForce(a, b, p), expected, 1e-9) << "segment " << i;
    }
  }
  EXPECT_GT(touching, 100);  // the random cases include intersecting segments
}

/// Sweeps that barely reach a hull: tangent to the hull grown by r, passing at r (1 - eps) from a
/// vertex, an edge or a face. There the distance along the sweep is flat at the contact, the hard
/// case for the lower bounds firstContact steps by.
TEST(ConvexDistance, FirstContactOnGrazingSweeps) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  const auto hulls = randomHulls(rng, 20);
  int checked = 0;
  for (const auto& hull : hulls) {
    const auto p = ConvexPolytope::fromHull(hull, "test");
    for (int i = 0; i < 60; ++i) {
      const double r = 0.05 + 0.1 * (i % 3);
      const auto& tri = hull.triangles[rng() % hull.triangles.size()];
      const V3 &A = hull.vertices[tri[0]], &B = hull.vertices[tri[1]], &C = hull.vertices[tri[2]];
      double u = unit(rng), v = unit(rng);
      if (u + v > 1) u = 1 - u, v = 1 - v;
      const V3 on = i % 3 == 0 ? A : (i % 3 == 1 ? V3(A + u * (B - A)) : V3(A + u * (B - A) + v * (C - A)));
      const V3 out = ((B - A).cross(C - A).normalized() + 0.5 * randomPoint(rng, 0.5)).normalized();
      const double eps = std::array<double, 4>{1e-2, 1e-4, 1e-5, 1e-6}[i % 4];
      const V3 tangent = out.cross(randomPoint(rng, 1.0)).normalized();
      const double length = 0.5 + 2.5 * unit(rng), before = unit(rng) * length;
      const V3 q = on + r * (1 - eps) * out;
      const V3 a = q - before * tangent, b = q + (length - before) * tangent;
      const double tol = std::max(1e-3, 1e-3 / length);
      const double whole = test::segmentHull(a, b, hull);
      if (std::abs(whole - r) < 1e-8) continue;  // grazing within the oracle's own precision
      const std::optional<double> contact = firstContact(a, b, p, r, tol);
      ASSERT_LE(whole, r) << "the sweep passes within r(1 - eps) of the hull";
      ASSERT_TRUE(contact);
      const double t = *contact;
      ASSERT_GE(t, 0.0);
      ++checked;
      EXPECT_LE(test::segmentHull(a, a + t * (b - a), hull), r + 1e-9) << "sweep " << i;
      if (t > tol) {
        EXPECT_GT(test::segmentHull(a, a + (t - tol) * (b - a), hull), r - 1e-9) << "sweep " << i;
      }
    }
  }
  EXPECT_GT(checked, 1000);
}

}  // namespace
}  // namespace hullmap::collision
