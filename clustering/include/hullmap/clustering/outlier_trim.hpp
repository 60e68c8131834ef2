#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/dbscan.hpp"

namespace hullmap::clustering {

/// Settings of trimOutliers().
struct OutlierTrimParams {
  /// A point with another point within this (map units) is not alone; and a point this close to a
  /// segment between two supporting points lies on the structure they sample. > 0.
  double radius = 0.15;
  /// Supporting points are looked for within this of the point (map units), >= radius.
  double reach = 0.6;
};

/// What trimOutliers() did.
struct OutlierTrim {
  std::size_t dropped = 0;  ///< clustered points made noise
};

/// Drops from the clusters the outliers that a wide eps took in. On a sparse map the eps that
/// connects a surface's own points (0.3 to 0.4 m at V1_01's density) also reaches a stray map point
/// that far in front of it, and DBSCAN makes that point a border point of the surface's cluster: an
/// obstacle voxel in free space, the room's side of a wall. Such a point is alone (nothing within
/// `radius`), and it lies on no structure: no segment between two points that sample a structure
/// near it passes by it. A real sample of a thin thing (a table leg seen as a point every 20 cm, a
/// box's edge) lies on the line between the samples above and below it, or around it. Exactly:
/// - A point p with label >= 0 that is not core (DBSCAN's core flag: it has its own density) is
///   dropped (labelled kNoise) when both hold:
///   1. no other point of `points` (any label) and no point of `support` lies within radius of p
///      (squared distance <= radius^2);
///   2. for no two points q != s, each either a point of `points` other than p with label >= 0 or a
///      point of `support`, both within reach of p (squared distance <= reach^2), does the segment
///      q s come within radius of p.
/// - Every point is decided on the labels given (all at once): two outliers do not hold each other up
///   by being dropped in turn, and the result does not depend on the order of the points.
/// `support`: points that sample structure but are not clustered (a build's floor and ceiling
/// voxels: a leg's foot stands on the floor); never dropped. `result.labels`, `cluster_sizes` and
/// `noise` are updated in place; `core` is unchanged (a dropped point is not core). Deterministic,
/// thread-safe (no shared state). Throws hullmap::Error naming the parameter on radius <= 0, reach <
/// radius (or not finite), a size mismatch between points, labels and core flags, or a non-finite point.
/// Cost: a hash grid of cells of side reach; only the clustered, non-core points with nothing within
/// radius (a few hundred on a room's 8,000 voxels) look at the pairs of points within reach.
OutlierTrim trimOutliers(const std::vector<Eigen::Vector3d>& points, DbscanResult& result,
                         const std::vector<Eigen::Vector3d>& support, const OutlierTrimParams& params);

}  // namespace hullmap::clustering
