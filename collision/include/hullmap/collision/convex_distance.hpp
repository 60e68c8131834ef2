#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/hulls/obstacles.hpp"

namespace hullmap::collision {

/// A convex polytope ready for exact queries: vertices (V-representation), outward triangles and one
/// outward half-space per triangle (H-representation: n.x <= offset, |n| = 1), and its AABB.
/// Map frame, map units. Immutable after construction; safe to query from many threads.
struct ConvexPolytope {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> offsets;
  Eigen::Vector3d aabb_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d aabb_max = Eigen::Vector3d::Zero();
  double scale = 1.0;  ///< max |coordinate|, for relative tolerances

  /// Checks the hull is closed, convex and of positive volume; throws hullmap::Error naming `what`.
  static ConvexPolytope fromHull(const hulls::ConvexHull& hull, const std::string& what);
};

/// Distance between the segment [a, b] and the polytope (0 when they intersect), by GJK on the
/// Minkowski difference with a certificate: it stops only when the upper bound (a realised pair of
/// points) and the lower bound (a separating plane) agree within 1e-9 * max(1, scale) or 1e-10
/// relative; otherwise it falls back to segmentPolytopeDistanceBruteForce.
double segmentPolytopeDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const ConvexPolytope& polytope);

/// The same distance by exhaustion: 0 when the segment clipped by every half-space is not empty,
/// else the minimum over the triangles facing the segment of the segment-triangle distance.
double segmentPolytopeDistanceBruteForce(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                         const ConvexPolytope& polytope);

/// Distance between the segments [p0, p1] and [q0, q1].
double segmentSegmentDistance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                              const Eigen::Vector3d& q1);

/// The point of the triangle (a, b, c) closest to p (Ericson, Real-Time Collision Detection 5.1.5).
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c);

/// Distance between a point and the triangle (a, b, c): |p - closestPointOnTriangle(p, a, b, c)|.
double pointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c);

/// Smallest t in [0, 1] such that the sphere of `radius` swept from a to a + t (b - a) touches the
/// polytope, to within `t_tolerance` (the returned t is at or just after the true first contact,
/// at most `t_tolerance` after it); std::nullopt when the whole sweep stays clear. The contact is bracketed from below
/// (where the segment enters the face planes pushed out by `radius`, then certified Newton steps on the point's
/// distance, which is convex in t) and confirmed by a distance within `radius` at most `t_tolerance`
/// later; bisection on the prefix distance where the distance cannot decide.
std::optional<double> firstContact(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const ConvexPolytope& polytope,
                                   double radius, double t_tolerance);

}  // namespace hullmap::collision
