#pragma once

#include <cstddef>
#include <vector>

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

/// Warnings for a path check against the hulls of such a build, which cannot see noise voxels:
/// kCheckNoObstacle (every path is clear; occupied_voxels), else kCheckMostlyNoise (noise_voxels,
/// occupied_voxels). `occupied_voxels` 0 means unknown (an obstacles.json without its report).
std::vector<Warning> hullCheckWarnings(const ClusteringOutcome& outcome);

}  // namespace hullmap::clustering
