#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/dbscan.hpp"

namespace hullmap::clustering {

/// A second, sparser density level after DBSCAN, which only grows the clusters DBSCAN found: the
/// sparse structure attached to them (a table's thin legs, a shelf's edge, a wall's foot, seen with
/// one or two map points per voxel) is kept, while noise that no cluster reaches stays noise.
struct ClusterExtensionParams {
  double eps = 0.1;     ///< density radius, map units (DBSCAN's test: squared distance <= eps^2), > 0
  int min_pts = 5;      ///< a noise point may join when the weight within eps, itself included, is >= min_pts, >= 1
  double reach = 0.15;  ///< ... and a dense clustered point lies within reach (map units), >= eps
  Metric metric = Metric::kXyz;
};

/// What extendClusters did.
struct ClusterExtension {
  std::size_t joined = 0;  ///< noise points that joined a cluster
  std::size_t rounds = 0;  ///< rounds in which some point joined (the longest chain, in hops)
};

/// Grows the clusters of a DBSCAN result through the points that are dense at a lower level,
/// hierarchical-DBSCAN style (HDBSCAN* looks at every density level; this looks at one more, and
/// only to extend the clusters of the first). Exactly, with d the distance under `params.metric`
/// (squared differences summed per axis in axis order, as dbscan()):
/// - A point p is *dense* when the summed weight of the points q with d(p,q)^2 <= eps^2 (every
///   point counts, clustered or not, p itself included) is >= min_pts.
/// - Rounds k = 0, 1, ...: L_k is the set of clustered points (L_0: those DBSCAN clustered, core or
///   border). Every dense noise point p with some dense q in L_k at d(p,q)^2 <= reach^2 joins, all
///   at once, the cluster of the nearest such q (among equally near ones, the lowest index). L_{k+1}
///   = L_k with them. It stops at the first round in which nothing joins.
/// - So a noise point joins only when a chain of dense points, each within reach of the next, links
///   it to a cluster; a point alone within eps (weight 1 < min_pts when min_pts >= 2) never joins.
///   No cluster is created (dense noise that no cluster reaches stays noise), none merge, no
///   clustered point changes its label, and `core` is left as is (a joined point is no DBSCAN core).
/// `result.labels`, `cluster_sizes` (points per cluster) and `noise` are updated in place.
///
/// `weights` empty means weight 1 a point, else one positive weight per point as for dbscan().
/// Throws hullmap::Error naming the parameter on eps <= 0, min_pts < 1, reach < eps (or not finite),
/// a size mismatch between points, weights and labels, a label < kNoise or >= cluster_sizes.size(),
/// a zero weight or a non-finite point. Deterministic whatever the thread count; thread-safe (no
/// shared state); uses the TBB arena of the caller.
/// Cost: docs/DESIGN_NOTES.md, "cluster_extension.hpp: cost".
ClusterExtension extendClusters(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
                                DbscanResult& result, const ClusterExtensionParams& params);

/// How the pipeline sets ClusterExtensionParams from the DBSCAN parameters it used (docs/CLI.md,
/// build stage 5): eps the same, min_pts = max(min_min_pts, floor(min_pts_factor * minPts)), reach =
/// reach_factor * eps. Why these defaults:
/// docs/DESIGN_NOTES.md, "cluster_extension.hpp: the defaults".
struct ClusterExtensionRule {
  double min_pts_factor = 0.3;  ///< in (0, 1]
  double reach_factor = 1.5;    ///< >= 1
  int min_min_pts = 2;          ///< >= 1
};

/// The extension's parameters for DBSCAN run with `used` under `rule`. Throws hullmap::Error naming
/// the rule's field when it is out of range, or eps when used.eps is not finite and > 0.
ClusterExtensionParams extensionParams(const DbscanParams& used, const ClusterExtensionRule& rule = {});

}  // namespace hullmap::clustering
