#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace hullmap::hulls {

/// A convex polyhedron: vertices and triangles whose vertex order is counter-clockwise seen from
/// outside (outward normals, right-hand rule).
struct ConvexHull {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// 2D footprint in the ground plane (z up): a convex polygon, counter-clockwise, plus its z range.
struct Footprint {
  std::vector<Eigen::Vector2d> polygon;
  double z_min = 0.0;
  double z_max = 0.0;
};

/// One convex part of an obstacle (see convex_parts.hpp): a subset of its cluster's voxels wrapped
/// conservatively like the whole. Map frame (z up), map units.
struct ObstaclePart {
  std::size_t voxel_count = 0;
  std::uint64_t point_weight = 0;  ///< map points in its voxels
  Eigen::Vector3d aabb_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d aabb_max = Eigen::Vector3d::Zero();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< of the hull volume
  double volume = 0.0;                                 ///< of the hull
  ConvexHull hull;                                     ///< contains every voxel of the part completely
  Footprint footprint;
  /// Certified bound (map units) on the distance from the hull to the part's own voxel cubes: at
  /// most T (G when `flat` or `faces`); a single voxel is exempt (its hull is its cube).
  double concavity_bound = 0.0;
  /// The part passed as flat: its hull is at most T thick (a wall, a table top), so the gaps in its
  /// surface, up to G, swallow no more than that slab (see ConvexPartsParams::flat_gap).
  bool flat = false;
  /// The part's bound counted the inside of its closed shell as its own (ConvexPartsParams::fill_enclosed).
  bool filled = false;
  /// The part passed by the face-hole rule (ConvexPartsParams::face_holes): its hull's points farther
  /// than T from its voxels lie within T of a face of the hull, within G of a voxel on that face.
  bool faces = false;
  std::size_t free_voxels_inside = 0;  ///< observed-free voxel centres given that lie in the hull
  /// Of those, the ones with none of the part's voxels among their 26 neighbours: free space
  /// swallowed beyond the one-voxel band along the surface (docs/CONVEX_PARTS.md, "Free voxels").
  std::size_t free_voxels_off_surface = 0;
};

/// One obstacle: a DBSCAN cluster of occupied voxels wrapped conservatively.
struct Obstacle {
  int id = 0;  ///< cluster label
  std::size_t voxel_count = 0;
  std::uint64_t point_weight = 0;  ///< map points in its voxels
  Eigen::Vector3d aabb_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d aabb_max = Eigen::Vector3d::Zero();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< of the hull volume
  double volume = 0.0;
  ConvexHull hull;  ///< contains every voxel of the cluster completely
  Footprint footprint;
  /// Convex parts of the cluster (convex_parts.hpp); empty when not split. The fields above always
  /// describe the whole cluster (the hull of all its voxels).
  std::vector<ObstaclePart> parts;
};

/// Whether `p` lies in the closed hull (inside or on its boundary, to 1e-9 of the hull's size).
/// Same frame and units as the hull. A hull of no triangle contains nothing.
bool hullContains(const ConvexHull& hull, const Eigen::Vector3d& p);

/// Wraps each cluster: hull of the voxels' corners (CGAL), footprint (Andrew's monotone chain).
/// `centers`/`weights`/`labels` are per voxel; `voxel_size` the leaf edge length.
std::vector<Obstacle> buildObstacles(const std::vector<Eigen::Vector3d>& centers,
                                     const std::vector<std::uint32_t>& weights, const std::vector<std::int32_t>& labels,
                                     double voxel_size);

}  // namespace hullmap::hulls
