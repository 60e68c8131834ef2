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

TEST(ConvexDistance, GrazingFacesAndEndPointContacts) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> unit(0, 1);
  const auto hulls = randomHulls(rng, 30);
  for (const auto& hull : hulls) {
    const auto p = ConvexPolytope::fromHull(hull, "test");
    for (std::size_t f = 0; f < hull.triangles.size(); ++f) {
      const auto& t = hull.triangles[f];
      const V3 &A = hull.vertices[t[0]], &B = hull.vertices[t[1]], &C = hull.vertices[t[2]];
      const V3 n = (B - A).cross(C - A).normalized();
      double u = unit(rng), v = unit(rng);
      if (u + v > 1) u = 1 - u, v = 1 - v;
      const V3 q = A + u * (B - A) + v * (C - A);  // on the face
      const V3 along = (B - A).normalized();
      for (const double offset : {0.0, 1e-6, 0.05, 0.3}) {
        // Parallel to the face at `offset`: the face's plane supports the hull, q is on it.
        const V3 a = q + offset * n - 0.7 * along, b = q + offset * n + 0.9 * along;
        EXPECT_NEAR(segmentPolytopeDistance(a, b, p), offset, 1e-9);
        EXPECT_NEAR(segmentPolytopeDistanceBruteForce(a, b, p), offset, 1e-9);
        // Ending exactly at the face point (or `offset` in front of it), coming from outside.
        const V3 from = q + (offset + 0.5) * n + 0.2 * along;
        EXPECT_NEAR(segmentPolytopeDistance(from, q + offset * n, p), offset, 1e-9);
        // Ending on a vertex of the face.
        EXPECT_NEAR(segmentPolytopeDistance(A + (offset + 0.4) * n, A + offset * n, p), offset, 1e-9);
      }
      // Along an edge's line, touching the edge end to end, and crossing the face.
      EXPECT_NEAR(segmentPolytopeDistance(A, B, p), 0.0, 1e-9);
      EXPECT_NEAR(segmentPolytopeDistance(q + n, q - 0.01 * n, p), 0.0, 1e-9);
    }
  }
}

TEST(ConvexDistance, FirstContactBracketsTheTrueContact) {
  std::mt19937 rng(3);
  const auto hulls = randomHulls(rng, 20);
  int checked = 0;
  for (const auto& hull : hulls) {
    const auto p = ConvexPolytope::fromHull(hull, "test");
    for (int i = 0; i < 60; ++i) {
      const V3 a = randomPoint(rng, 1.5), b = randomPoint(rng, 1.5);
      const double r = 0.05 * (i % 4);
      const double tol = std::max(1e-3, 1e-3 / (b - a).norm());
      const std::optional<double> contact = firstContact(a, b, p, r, tol);
      if (test::segmentHull(a, b, hull) > r + 1e-9) {
        EXPECT_FALSE(contact) << *contact;
        continue;
      }
      ASSERT_TRUE(contact);
      const double t = *contact;
      ASSERT_GE(t, 0.0);
      ++checked;
      EXPECT_LE(test::segmentHull(a, a + t * (b - a), hull), r + 1e-9);
      if (t > tol) {
        EXPECT_GT(test::segmentHull(a, a + (t - tol) * (b - a), hull), r - 1e-9);
      }
    }
  }
  EXPECT_GT(checked, 50);
}

TEST(ConvexDistance, RejectsInvalidHulls) {
  hulls::ConvexHull flat;
  flat.vertices = {V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), V3(1, 1, 0)};
  flat.triangles = {{0, 1, 2}, {1, 3, 2}, {0, 2, 1}, {1, 2, 3}};
  EXPECT_THROW(ConvexPolytope::fromHull(flat, "flat"), Error);
  hulls::ConvexHull inward;
  inward.vertices = {V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), V3(0, 0, 1)};
  inward.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};  // all clockwise from outside
  EXPECT_THROW(ConvexPolytope::fromHull(inward, "inward"), Error);
  std::swap(inward.triangles[0][1], inward.triangles[0][2]);
  std::swap(inward.triangles[1][1], inward.triangles[1][2]);
  std::swap(inward.triangles[2][1], inward.triangles[2][2]);
  std::swap(inward.triangles[3][1], inward.triangles[3][2]);
  EXPECT_NO_THROW(ConvexPolytope::fromHull(inward, "tetrahedron"));
}

}  // namespace
}  // namespace hullmap::collision
