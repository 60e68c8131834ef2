#pragma once
// Private to hullmap_clustering: the voxel-lattice helpers of obstacles.cpp that convex_parts.cpp
// shares.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/obstacles.hpp"

namespace hullmap::clustering::detail {

/// Corners (integer lattice, corner (i, j, k) of cell (i, j, k) is its lower corner) that can be
/// vertices of the hull of all the cells' corners. Never drops a hull vertex; order unspecified.
std::vector<std::array<std::int64_t, 3>> candidateCorners(const std::vector<std::array<std::int64_t, 3>>& cells);

/// The obstacle of the voxels `members` (indices into centers/weights): the hull of their corners,
/// canonical, with footprint, volume, centroid and box. `parts` is left empty.
Obstacle wrapCluster(int id, const std::vector<std::size_t>& members, const std::vector<Eigen::Vector3d>& centers,
                     const std::vector<std::uint32_t>& weights, double voxel_size);

}  // namespace hullmap::clustering::detail
