#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/dbscan.hpp"

namespace hullmap::clustering {

/// Settings of mergeCoplanarClusters().
struct CoplanarMergeParams {
  double reach = 0.4;  ///< a flat cluster may join a larger one with a point within this of its own (map units), > 0
  double thickness = 0.15;  ///< a point set is flat when it is at most this thick (map units), > 0
};

/// What mergeCoplanarClusters() did.
struct CoplanarMerge {
  std::size_t merged = 0;  ///< clusters joined to another
  std::size_t points = 0;  ///< their points
};

/// Joins each flat cluster to the larger cluster whose points around it lie in the same plane: a
/// stretch at a wall's foot, denser than the sparse wall above it (the foot is an edge, sampled more),
/// or a poster on a wall (why they split off: docs/DESIGN_NOTES.md, "coplanar_merge.hpp"). Exactly:
/// - The *thickness* of a set of at least 3 points is the extent (largest minus smallest value of
///   n . p) of its points along the unit eigenvector n of the smallest eigenvalue of their
///   covariance (Eigen::SelfAdjointEigenSolver); the set is *flat* when that is <= params.thickness.
/// - For each cluster B of at least 3 points whose points are flat, and each cluster A larger than
///   B (more points; equal sizes: the lower label) with a point within params.reach of a point of B
///   (squared distance <= reach^2): A's *surface around B* is its m points nearest to B (distance to
///   the nearest point of B; ties: the lower index) among those within 2 reach of B, m = max(3, |B|),
///   when there are at least 3 such points. B joins the A with the most points within 2 reach of B
///   (ties: the lower label) among those where B's points together with A's surface around B are
///   flat, and A's surface around B spans that plane: its extent along the eigenvector of the middle
///   eigenvalue of the union's covariance is at least 2 thickness (a wall's foot, a row of voxels,
///   lies in the plane of a patch of floor by it, but the wall does not). Decisions are taken on the
///   labels as given, then applied (a chain B -> A -> C ends in C).
/// - Labels are then renumbered 0..k-1 in the order of each cluster's first point, as dbscan()
///   numbers them; cluster_sizes and noise follow. Noise stays noise; `core` is left as it is.
/// A cluster at a corner of two walls, or a box, a table top or a shelf by a wall, is not flat
/// together with the wall around it, so it stays. Deterministic whatever the thread count. Throws
/// hullmap::Error naming the parameter when reach or thickness is not finite and > 0, or on a size
/// mismatch between points and labels.
CoplanarMerge mergeCoplanarClusters(const std::vector<Eigen::Vector3d>& points, DbscanResult& result,
                                    const CoplanarMergeParams& params);

/// The thickness defined above, of the points `indices` picks (0 for fewer than 3 points).
double pointSetThickness(const std::vector<Eigen::Vector3d>& points, const std::vector<std::size_t>& indices);

}  // namespace hullmap::clustering
