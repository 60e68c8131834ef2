#pragma once
// Private to hullmap_collision: a capsule against the solid under a height field (the ground
// outdoors), as the checkers fold surfaces in (path_check.cpp). Exposed to its tests.

#include <array>

#include <Eigen/Core>

#include "hullmap/collision/convex_distance.hpp"
#include "hullmap/collision/path_check.hpp"

namespace hullmap::collision::detail {

/// The convex prism under the triangle `top` (three points of distinct x, y) down to z = bottom
/// (below every top vertex), with its outward faces.
ConvexPolytope groundPrism(const std::array<Eigen::Vector3d, 3>& top, double bottom);

/// The segment swept by a sphere of `radius` against the solid under `surface.field` (inputs
/// validated): the solid is the union of the prisms under the field's triangles, each exact
/// (certified distances, firstContact); the earliest contact over the prisms within radius, to
/// `t_tolerance` (a fraction of the segment); else the least distance minus radius as clearance.
/// Only prisms that may lie within reach are computed: the cells of the triangles whose (x, y)
/// rectangle lies within the reach of the segment's (x, y) and whose highest node is not below it
/// by more than the reach; the reach is the radius or the segment's height over the surface at an
/// end, whichever is larger (the surface point below an end is that close), then the nearest found.
SegmentCheck sweepHeightField(const Segment& segment, double radius, const Surface& surface, double t_tolerance);

}  // namespace hullmap::collision::detail
