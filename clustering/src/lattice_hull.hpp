#pragma once
// Private to hullmap_clustering: the voxel-lattice helpers of obstacles.cpp that convex_parts.cpp
// shares.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/obstacles.hpp"

namespace hullmap::clustering::detail {

/// The lattice index of the voxel centred at `center` on the lattice whose cell (0, 0, 0) has its
/// lower corner at `origin` (cells of side voxel_size): the nearest integers to the cell's offset, so
/// centres a rounding error off the lattice still land in their own cell. buildObstacles and the
/// convex split must index a cluster identically: both call this.
inline std::array<std::int64_t, 3> latticeIndex(const Eigen::Vector3d& center, const Eigen::Vector3d& origin,
                                                double voxel_size) {
  const Eigen::Vector3d rel = (center - origin) / voxel_size - Eigen::Vector3d::Constant(0.5);
  return {std::llround(rel.x()), std::llround(rel.y()), std::llround(rel.z())};
}

/// Corners (integer lattice, corner (i, j, k) of cell (i, j, k) is its lower corner) that can be
/// vertices of the hull of all the cells' corners. Never drops a hull vertex; order unspecified.
std::vector<std::array<std::int64_t, 3>> candidateCorners(const std::vector<std::array<std::int64_t, 3>>& cells);

/// The obstacle of the voxels `members` (indices into centers/weights): the hull of their corners,
/// canonical, with footprint, volume, centroid and box. `parts` is left empty.
Obstacle wrapCluster(int id, const std::vector<std::size_t>& members, const std::vector<Eigen::Vector3d>& centers,
                     const std::vector<std::uint32_t>& weights, double voxel_size);

}  // namespace hullmap::clustering::detail
