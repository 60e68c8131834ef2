#pragma once
// The voxel lattice of a cluster (cell (i, j, k) is the cube [i, i+1] x [j, j+1] x [k, k+1] in voxel
// units) and the hulls on it: a white-box header for hullmap_hulls and its tests, not installed.
//
// Why two hull algorithms: docs/CONVEX_PARTS.md, "Two hull algorithms".

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <tuple>
#include <vector>

#include <Eigen/Core>

#include "hullmap/hulls/obstacles.hpp"

namespace hullmap::hulls::detail {

/// A cell or corner of the lattice.
using LatticePoint = std::array<std::int64_t, 3>;

/// A facet plane of a lattice hull: n . x <= d inside, x in corner-lattice coordinates (cell (i, j, k)
/// is the cube [i, i+1] x [j, j+1] x [k, k+1]); n primitive.
struct Plane {
  LatticePoint n;
  std::int64_t d;
  bool operator<(const Plane& o) const { return std::tie(n, d) < std::tie(o.n, o.d); }
};

struct FacetHull {
  std::vector<Plane> planes;  ///< sorted, one per facet
  std::int64_t volume6 = 0;   ///< six times the volume, exact (cells^3)
};

inline LatticePoint sub(const LatticePoint& a, const LatticePoint& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline LatticePoint cross(const LatticePoint& a, const LatticePoint& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline std::int64_t dot(const LatticePoint& a, const LatticePoint& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// Hull of the cells' corners, exact on the lattice: its facet planes and volume do not depend on
/// how it is triangulated, so everything decided from them is deterministic. `cells` is not empty
/// (the corners of any cell are not coplanar).
FacetHull facetHull(const std::vector<LatticePoint>& cells);

/// Whether x (corner-lattice coordinates) lies in the hull, with a tolerance of 1e-9.
inline bool inside(const FacetHull& hull, const Eigen::Vector3d& x) {
  for (const auto& p : hull.planes)
    if (double(p.n[0]) * x.x() + double(p.n[1]) * x.y() + double(p.n[2]) * x.z() > double(p.d) + 1e-9) return false;
  return true;
}

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

/// The volume of a closed hull with outward triangles and its centroid (by the divergence theorem,
/// tetrahedra from its first vertex); the centroid is `fallback` when the volume is not positive.
std::pair<double, Eigen::Vector3d> volumeAndCentroid(const ConvexHull& hull, const Eigen::Vector3d& fallback);

/// The obstacle of the voxels `members` (indices into centers/weights): the hull of their corners,
/// canonical, with footprint, volume, centroid and box. `parts` is left empty.
Obstacle wrapCluster(int id, const std::vector<std::size_t>& members, const std::vector<Eigen::Vector3d>& centers,
                     const std::vector<std::uint32_t>& weights, double voxel_size);

}  // namespace hullmap::hulls::detail
