#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/dbscan.hpp"

namespace hullmap::clustering {

/// The rule behind `--eps auto` / `--min-pts auto`. Everything is measured on the occupied voxel
/// centres (the points DBSCAN clusters) in voxel sizes, and on their weights (map points per voxel),
/// so the result scales with the map: scaling the map and the resolution together by s scales eps
/// by s and leaves minPts unchanged.
///
/// 1. Spacing: for a sample of voxels (every voxel when there are at most `sample` of them, else
///    `sample` voxels drawn with a fixed seed), the distance to the k-th nearest other occupied
///    voxel, looked for up to max_eps_voxels * resolution (farther counts as infinite). d = the
///    `knn_quantile` quantile of those distances, each sampled voxel weighing its map points (so it
///    is the spacing around the typical map point: a dense map's outliers, one point in a voxel each,
///    may be most of its voxels but few of its points): a high quantile, because ORB-SLAM's points
///    crowd on edges and corners and the sparse faces between them must connect too. On a surface
///    seen with one map point per few voxels, d is the typical gap between the points; on a dense
///    surface it is about one voxel.
/// 2. eps = eps_factor * d, clamped to [min_eps_voxels, max_eps_voxels] * resolution. The lower
///    bound (> sqrt(3)) makes face-, edge- and corner-adjacent voxels neighbours; the upper bound
///    keeps obstacles max_eps_voxels voxels apart (0.4 m at 5 cm) from merging, however sparse.
/// 3. minPts = the `min_pts_quantile` quantile of the neighbourhood weight (DBSCAN's: the summed
///    weight within eps, the voxel included) over the sampled voxels that lie on a structure (at
///    least k other voxels within eps), each weighing its own map points as in 1, at least
///    `min_min_pts`: the voxels holding about (1 - quantile) of the structure's points are core, so walls and furniture
///    form clusters, while an isolated outlier voxel (alone within eps) is not core. Outliers are left out of the
///    quantile: on a map with many of them they would pull it down to 1. No structured voxel: minPts = min_min_pts.
///
/// Cost: one pass over the voxels (gathering those near the sample into a hash grid of cells of
/// max_eps_voxels * resolution), then two passes over the neighbourhoods of the `sample` voxels
/// within max_eps_voxels: about 35 to 125 ms, one thread, on 262,000 voxels where DBSCAN takes 0.6
/// to 1.1 s on two cores (a loaded machine), so 6 to 8 % of it.
struct AutoParamsRule {
  int k = 4;                       ///< k-th nearest occupied voxel, >= 1
  double knn_quantile = 0.75;      ///< which k-NN distance sets eps, in [0, 1]
  double eps_factor = 2.0;         ///< eps = eps_factor * that k-NN distance, > 0
  double min_eps_voxels = 1.8;     ///< lower clamp of eps, in voxel sizes
  double max_eps_voxels = 8.0;     ///< upper clamp of eps, in voxel sizes (>= min_eps_voxels)
  double min_pts_quantile = 0.05;  ///< in [0, 1]
  int min_min_pts = 3;             ///< >= 1
  std::size_t sample = 512;        ///< voxels measured, >= 1
  std::uint64_t seed = 1;
};

/// The chosen values and what they were chosen from.
struct AutoParams {
  double eps = 0.0;  ///< map units
  int min_pts = 1;
  double knn = 0.0;            ///< the knn_quantile k-NN distance, map units; +inf when beyond reach
  double eps_unclamped = 0.0;  ///< eps_factor * knn
  std::size_t sampled = 0;     ///< voxels measured
  std::size_t structured = 0;  ///< of those, voxels with k other voxels within eps
};

/// Chooses DBSCAN's eps and minPts for occupied voxel centres of side `resolution` (map units) and
/// their weights (empty: 1 each), by `rule` (see AutoParamsRule), under `metric` (kXy measures
/// distances on x, y only). An empty input gives eps = min_eps_voxels * resolution and minPts =
/// min_min_pts. Throws hullmap::Error naming --eps on a resolution that is not finite and > 0, a bad
/// rule, non-finite centres or a weight-count mismatch. Deterministic; thread-safe (no shared state).
AutoParams chooseDbscanParams(const std::vector<Eigen::Vector3d>& centres, const std::vector<std::uint32_t>& weights,
                              double resolution, Metric metric = Metric::kXyz, const AutoParamsRule& rule = {});

}  // namespace hullmap::clustering
