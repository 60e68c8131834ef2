#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "hullmap/clustering/dbscan.hpp"

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

/// One-line warnings about a clustering whose hulls leave out much of the map, for `hullmap build`
/// to print and record in report.json; empty when there is nothing to say. Warns when eps is below
/// the resolution (neighbouring voxel centres are `resolution` apart, so with the xyz metric no two
/// voxels are neighbours and every cluster is one voxel heavy enough alone), when there is no
/// obstacle although voxels are occupied, and when more than kNoiseShareLimit of the occupied
/// voxels are noise. Parameters are named as the CLI spells them (--eps, --min-pts, --resolution).
std::vector<std::string> buildWarnings(const ClusteringOutcome& outcome);

/// One-line warnings for a path check against the hulls of such a build: path checks against the
/// hulls cannot see noise voxels, so with no obstacle every path is clear, and with mostly noise
/// most of the map is invisible to them. Each names the remedy (--against octree, another --eps or
/// --min-pts). `occupied_voxels` 0 means unknown (an obstacles.json without its report).
std::vector<std::string> hullCheckWarnings(const ClusteringOutcome& outcome);

}  // namespace hullmap::clustering
