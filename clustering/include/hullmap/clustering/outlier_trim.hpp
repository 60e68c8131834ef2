#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/dbscan.hpp"

namespace hullmap::clustering {

/// Settings of trimOutliers().
struct OutlierTrimParams {
  /// A point with another point within this (map units) is not alone; a point farther than this off
  /// the slab of a patch at most this thick stands off it. > 0.
  double radius = 0.15;
  /// The patch is made of the supporting points within this of the point (map units), >= radius.
  double reach = 0.6;
};

/// What trimOutliers() did.
struct OutlierTrim {
  std::size_t dropped = 0;  ///< clustered points made noise
};

/// Drops from the clusters the outliers that a wide eps took in off a surface. A point alone that
/// stands off a flat patch it would sit on is dropped (why: docs/DESIGN_NOTES.md, "outlier_trim.hpp"). Exactly:
/// - A *loner* is a point of `points` with label >= 0 that is not core (DBSCAN's core flag) and has
///   no other point of `points` (any label) nor of `support` within radius (squared distance <=
///   radius^2).
/// - A loner p is dropped (labelled kNoise) when its *patch* Q, the points within reach of p (squared
///   distance <= reach^2) that are either points of `support` or points of `points` with label >= 0
///   that are no loners, in index order (`points` first), holds at least 3 points and:
///   1. Q is at most radius thick: with n the unit eigenvector of the smallest eigenvalue of Q's
///      covariance (Eigen::SelfAdjointEigenSolver), max - min of n . q over Q <= radius;
///   2. p lies farther than radius outside that slab: n . p > max + radius or < min - radius;
///   3. p's projection on the other two eigenvectors lies in the convex hull (convexHull2d, closed)
///      of Q's projections.
/// - Loners do not support each other (two outliers do not hold each other up), and every point is
///   decided on the labels given: the result does not depend on the order of the points.
/// `support`: points that sample structure but are not clustered (a build's floor and ceiling
/// voxels: a leg's foot stands on the floor); never dropped. `result.labels`, `cluster_sizes` and
/// `noise` are updated in place; `core` is unchanged. Deterministic, thread-safe (no shared state).
/// Throws hullmap::Error naming the parameter on radius <= 0, reach < radius (or not finite), a size
/// mismatch between points, labels and core flags, or a non-finite point. Cost: a hash grid of cells
/// of side reach; only the loners look at their patch.
OutlierTrim trimOutliers(const std::vector<Eigen::Vector3d>& points, DbscanResult& result,
                         const std::vector<Eigen::Vector3d>& support, const OutlierTrimParams& params);

}  // namespace hullmap::clustering
