#pragma once
// Internals of the certified distance shared by convex_distance.cpp and path_check.cpp. Not installed.

#include <Eigen/Core>

#include "hullmap/collision/convex_distance.hpp"

namespace hullmap::collision {

namespace detail {

/// A distance with its proof: `upper` is realised by a pair of points (the distance is at most it),
/// and every point of the polytope x satisfies normal.(p - x) >= lower for every p of the segment
/// (so the distance is at least `lower`). normal is a unit vector, or zero when lower is 0.
struct DistanceCertificate {
  double upper = 0.0;
  double lower = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};

/// segmentPolytopeDistance with its certificate. Stops early, with a valid but loose certificate,
/// once `upper <= settle_at` or `lower > give_up_beyond` (for callers that only need to know which).
DistanceCertificate certifiedDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                      const ConvexPolytope& polytope, double settle_at, double give_up_beyond);

/// A t no later than the sweep's first contact: where [a, b] has crossed every face plane, pushed
/// out by `radius`, that a starts outside of. Greater than 1 proves the sweep stays clear.
double contactLowerBound(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const ConvexPolytope& polytope,
                         double radius);

/// firstContact for a sweep known to touch the polytope (distance of [a, b] <= radius), given a
/// lower bound on the contact (contactLowerBound, or 0).
double firstContactTouching(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const ConvexPolytope& polytope,
                            double radius, double t_tolerance, double lower_bound);

}  // namespace detail

}  // namespace hullmap::collision
