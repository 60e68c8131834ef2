#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "hullmap/clustering/auto_params.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/warning.hpp"

namespace hullmap::clustering {

/// What a build's clustering made of its octree: the numbers the warnings below judge.
struct ClusteringOutcome {
  std::size_t occupied_voxels = 0;  ///< occupied leaves of the octree
  std::size_t noise_voxels = 0;     ///< occupied voxels DBSCAN left in no cluster
  std::size_t obstacles = 0;        ///< convex obstacles (one per cluster)
  double eps = 0.0;                 ///< DBSCAN radius used, map units
  int min_pts = 0;                  ///< DBSCAN core threshold used, in map points
  Metric metric = Metric::kXyz;
  double resolution = 0.0;  ///< octree leaf size, map units
};

/// Share of occupied voxels left as noise above which a build is warned about (0.5: most of them).
inline constexpr double kNoiseShareLimit = 0.5;

/// Warnings about a clustering whose hulls leave out much of the map, for a build's report; empty
/// when there is nothing to say. kEpsBelowResolution (xyz metric: neighbouring voxel centres are
/// `resolution` apart, so no two voxels are neighbours and every cluster is one voxel heavy enough
/// alone) or kEpsBelowResolutionInColumns (numbers eps, resolution); kNoObstacle when voxels are
/// occupied and there is no obstacle (occupied_voxels, eps, min_pts); else kMostlyNoise when more
/// than kNoiseShareLimit of the occupied voxels are noise (noise_voxels, occupied_voxels).
std::vector<Warning> buildWarnings(const ClusteringOutcome& outcome);

/// The spacing a resolution is suggested for, in voxels: the auto rule's k-NN distance on the maps
/// that cluster well is 1.4 to 4.6 voxels (docs/CLI.md); 2.5 is in the middle of that range.
inline constexpr double kSuggestedSpacingVoxels = 2.5;

/// kSparseForResolution when the auto rule, measured on `centres` at `resolution` (`chosen`, by
/// `rule` under `metric`), found the typical map point's k-th nearest occupied voxel beyond its reach
/// (rule.max_eps_voxels voxels, AutoParams::knn infinite): eps is then clamped far below the points'
/// spacing, and most voxels are noise. Its numbers: `resolution`; `spacing`, the rule's knn_quantile
/// quantile of the exact, unbounded k-NN distance (kDistanceCurve over rule.sample voxels evenly
/// spread, unweighted: at such spacing a voxel holds about one point); `suggested`, spacing /
/// kSuggestedSpacingVoxels rounded down to 1, 2 or 5 x 10^n (never finer than `resolution`).
/// None otherwise, and when eps and minPts were both given (no `chosen`).
std::optional<Warning> sparseMapWarning(const std::vector<Eigen::Vector3d>& centres, double resolution,
                                        const AutoParams& chosen, const AutoParamsRule& rule, Metric metric);

/// A resolution rounded down to 1, 2 or 5 x 10^n (the largest not above `value`; > 0 and finite):
/// the voxels are then never coarser than the spacing asks.
double roundResolution(double value);

/// The spacing of `points` as sparseMapWarning measures it: the rule.knn_quantile quantile of the
/// exact distance from a point to its rule.k-th nearest (kDistanceCurve over rule.sample points
/// evenly spread, unweighted). nullopt for rule.k points or fewer.
std::optional<double> pointSpacing(const std::vector<Eigen::Vector3d>& points, const AutoParamsRule& rule,
                                   Metric metric);

/// The resolution a map of points `spacing` apart needs when `resolution` is too fine for it:
/// when spacing > rule.max_eps_voxels * resolution (the auto rule's reach: most voxels would be
/// noise), spacing / kSuggestedSpacingVoxels rounded by roundResolution; nullopt otherwise.
std::optional<double> resolutionForSpacing(double spacing, double resolution, const AutoParamsRule& rule);

/// Warnings for a path check against the hulls of such a build, which cannot see noise voxels:
/// kCheckNoObstacle (every path is clear; occupied_voxels), else kCheckMostlyNoise (noise_voxels,
/// occupied_voxels). `occupied_voxels` 0 means unknown (an obstacles.json without its report).
std::vector<Warning> hullCheckWarnings(const ClusteringOutcome& outcome);

}  // namespace hullmap::clustering
