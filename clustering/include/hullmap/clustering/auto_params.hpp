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
/// 1. Spacing d: the weighted `knn_quantile` quantile of the k-th nearest occupied voxel distance over
///    a sample of voxels (fixed seed), looked for up to max_eps_voxels * resolution.
/// 2. eps = eps_factor * d, clamped to [min_eps_voxels, max_eps_voxels] * resolution.
/// 3. minPts = the weighted `min_pts_quantile` quantile of the neighbourhood weight over sampled
///    voxels on a structure (>= k other voxels within eps), at least `min_min_pts`.
/// The full rule, its reasons and its cost: docs/DESIGN_NOTES.md, "auto_params.hpp: the rule".
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
