#pragma once
// Sparse edges: growing a convex part of a sparse surface in its own plane, so that its hull
// reaches the surface's edges (why: docs/CONVEX_PARTS.md, "Sparse edges").

#include "hullmap/hulls/obstacles.hpp"

namespace hullmap::hulls {

/// How much a sparse part grows. Its spacing s is sqrt(area / points): the area of its hull's
/// projection on its plane when it is flat, else half its hull's surface; the points are the map
/// points in its voxels (ObstaclePart::point_weight). It grows by factor * (s - onset), at most
/// cap, nothing when s <= onset. Lengths in voxel edges (at 5 cm voxels: onset 0.12 m, cap 0.1 m).
struct SparseEdges {
  double onset = 2.4;   ///< voxel edges: maps denser than this spacing keep their hulls as they are
  double factor = 1.5;  ///< growth per voxel edge of spacing beyond the onset
  double cap = 2.0;     ///< voxel edges: the most a part grows
};

/// The growth sparseEdges gives `part` (map units, >= 0). Throws hullmap::Error on bad parameters.
double sparseEdgeGrowth(const ObstaclePart& part, double voxel_size, const SparseEdges& params = {});

/// Grows `part` by sparseEdgeGrowth within its plane: its hull becomes the hull of its vertices
/// moved by that much in 12 directions of the plane of its two longest principal axes (the
/// Minkowski sum with a regular 12-gon of that circumradius), and its AABB, footprint, volume and
/// centroid follow; voxel counts, weights, the concavity bound and flags stay. The plane is that
/// of the hull's vertices' two largest principal axes; a part counts as flat when ObstaclePart::flat
/// says so or its thinnest extent is under a quarter of its middle one. Returns the growth (0: the
/// part is unchanged).
double growSparseEdges(ObstaclePart& part, double voxel_size, const SparseEdges& params = {});

}  // namespace hullmap::hulls
