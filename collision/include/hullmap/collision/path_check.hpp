#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/core/height_field.hpp"
#include "hullmap/hulls/obstacles.hpp"

namespace octomap {
class OcTree;
}

namespace hullmap::collision {

/// A straight segment of a path, map frame.
struct Segment {
  Eigen::Vector3d a;
  Eigen::Vector3d b;
};

/// A surface that bounds the map as a solid, an obstacle for every check: a plane (a floor, a
/// ceiling) or a height field (the ground outdoors).
/// - Plane (`field` empty): the half-space of every point x with normal . x <= offset. `normal` is
///   a unit vector pointing out of the solid, into the map: up for a floor (the solid below it),
///   down for a ceiling (the solid above it).
/// - Height field (`field` set; normal and offset unused): every point on or under the field's
///   surface (HeightField: linear on triangles between its nodes, level with its edges beyond them).
///   The solid reaches `field->step * (nx + ny)` around the nodes' span and as far below the
///   lowest node, the region a check of the map covers (kilometres for a street map on 2 m cells).
/// Map frame, map units. The checkers validate it (unit, finite normal and finite offset; a valid
/// field).
struct Surface {
  std::string name;  ///< what it is: "floor", "ceiling", "ground"
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
  std::shared_ptr<const HeightField> field;  ///< the ground's height field; empty for a plane

  /// A plane surface.
  static Surface plane(std::string name, const Eigen::Vector3d& normal, double offset) {
    Surface s;
    s.name = std::move(name);
    s.normal = normal;
    s.offset = offset;
    return s;
  }
  /// A height-field surface.
  static Surface heightField(std::string name, HeightField f) {
    Surface s;
    s.name = std::move(name);
    s.field = std::make_shared<const HeightField>(std::move(f));
    return s;
  }
  bool isPlane() const { return !field; }

  /// Plane: the signed distance of p to the plane, > 0 outside the solid (in the map). Height
  /// field: p's height over the surface, > 0 above it (outside the solid); not the distance to it
  /// (on a slope that is less), which the checks compute.
  double distance(const Eigen::Vector3d& p) const {
    return field ? p.z() - field->height(p.x(), p.y()) : normal.dot(p) - offset;
  }
};

/// Default of CheckRequest::contact_tolerance, map units.
inline constexpr double kContactTolerance = 1e-3;

/// How a check is asked, in the manner of FCL's request structs.
struct CheckRequest {
  double radius = 0.0;  ///< radius of the sphere swept along the segment (the drone), map units, >= 0
  /// Map units along the segment, > 0: the reported contact lies at or after the true first one, by
  /// at most max(contact_tolerance, 1e-3 * segment length).
  double contact_tolerance = kContactTolerance;
};

/// Result for one segment swept by a sphere of radius r (a capsule).
struct SegmentCheck {
  bool collides = false;
  int obstacle = -1;       ///< HullChecker: id (Obstacle::id) of the obstacle hit first; -1 when clear
                           ///< or in octree mode (voxels have no id)
  int part = -1;           ///< HullChecker: index of that obstacle's convex part hit first; -1 when
                           ///< clear, in octree mode, or for an obstacle without parts
  std::string surface;     ///< the name of the surface (Surface) hit first ("floor"); empty when
                           ///< clear or when a hull or voxel is hit first (obstacle, part then -1)
  double t = 1.0;          ///< first contact as a fraction of the segment (valid when collides)
  double clearance = 0.0;  ///< min distance to any obstacle minus r, map units; 0 when colliding
};

/// Result for a path of waypoints: one SegmentCheck per leg (one for a single waypoint).
struct PathCheck {
  std::vector<SegmentCheck> segments;
  std::optional<std::size_t> first_colliding_segment;
  std::optional<Eigen::Vector3d> first_contact;  ///< point on the path, map frame
};

/// A capsule (the segment swept by a sphere of `radius`) against one surface. A plane exactly: its
/// distance is linear along the segment, so the first contact is where it falls to `radius` (t = 0
/// when the segment starts within radius of the solid), and clearance is the smaller end's distance
/// minus radius. A height field: the exact distance to the union of the prisms under its
/// triangles (certified convex distances), the first contact within `contact_tolerance` as in the
/// checkers. `surface` is set to the surface's name when it collides. Throws hullmap::Error as the
/// checkers do on a bad radius, tolerance, segment or surface.
SegmentCheck checkSurface(const Segment& segment, double radius, const Surface& surface,
                          double contact_tolerance = kContactTolerance);

/// Hull mode: the obstacles' convex hulls (one per convex part when an obstacle has parts) as FCL objects in FCL's
/// broadphase manager (FclObstacles); every answer from certified segment-hull distances (convex_distance.hpp), the
/// first contact bracketed as firstContact does.
///
/// Coordinates in the obstacles' frame (hullmap's z-up map frame), map units. The constructor
/// copies the obstacles' hulls (as ConvexPolytope and FCL objects) and their ids; the vector given
/// may go away after it. Throws hullmap::Error on an invalid hull (naming its id); the checks throw
/// hullmap::Error naming `radius` (negative or not finite) or `contact_tolerance` (not > 0), or on a
/// non-finite coordinate. Immutable after construction: concurrent checks from several threads are
/// safe; checkBatch and checkPath themselves use all cores (TBB). Movable, not copyable.
///
/// `surfaces` (a found floor or ceiling: BuildResult::surfaces) are obstacles too: a segment that
/// comes within radius of one collides with it (SegmentCheck::surface names it), whichever of the
/// hulls and surfaces the sweep reaches first; clearance counts them. Throws hullmap::Error naming
/// `surfaces` when one has a non-unit or non-finite normal or a non-finite offset.
class HullChecker {
 public:
  explicit HullChecker(const std::vector<hulls::Obstacle>& obstacles, std::vector<Surface> surfaces = {});
  ~HullChecker();
  HullChecker(HullChecker&&) noexcept;
  HullChecker& operator=(HullChecker&&) noexcept;

  SegmentCheck check(const Segment& segment, const CheckRequest& request) const;
  PathCheck checkPath(const std::vector<Eigen::Vector3d>& waypoints, const CheckRequest& request) const;
  std::vector<SegmentCheck> checkBatch(const std::vector<Segment>& segments, const CheckRequest& request) const;

  /// The same with the default contact tolerance.
  SegmentCheck check(const Segment& segment, double radius) const { return check(segment, CheckRequest{radius}); }
  PathCheck checkPath(const std::vector<Eigen::Vector3d>& waypoints, double radius) const {
    return checkPath(waypoints, CheckRequest{radius});
  }
  std::vector<SegmentCheck> checkBatch(const std::vector<Segment>& segments, double radius) const {
    return checkBatch(segments, CheckRequest{radius});
  }

  /// The surfaces it checks against, as given.
  const std::vector<Surface>& surfaces() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Octree mode: the same questions against every occupied voxel of the map (FCL's OcTree and
/// FCL's capsule-box narrowphase, the first contact found by bisection on the swept prefix to the
/// request's tolerance). SegmentCheck::obstacle is always -1. The constructor copies the tree.
/// `surfaces` are obstacles as in HullChecker: a sparse floor has gaps between its voxels that a
/// thin sweep passes through, the floor's half-space has none; the ground's height field is the
/// surface under voxels set aside as ground.
/// Units, frame, errors and thread safety as HullChecker's. Movable, not copyable.
class OctreeChecker {
 public:
  explicit OctreeChecker(const octomap::OcTree& tree, std::vector<Surface> surfaces = {});
  ~OctreeChecker();
  OctreeChecker(OctreeChecker&&) noexcept;
  OctreeChecker& operator=(OctreeChecker&&) noexcept;

  SegmentCheck check(const Segment& segment, const CheckRequest& request) const;
  PathCheck checkPath(const std::vector<Eigen::Vector3d>& waypoints, const CheckRequest& request) const;

  /// The same with the default contact tolerance.
  SegmentCheck check(const Segment& segment, double radius) const { return check(segment, CheckRequest{radius}); }
  PathCheck checkPath(const std::vector<Eigen::Vector3d>& waypoints, double radius) const {
    return checkPath(waypoints, CheckRequest{radius});
  }

  /// The surfaces it checks against, as given.
  const std::vector<Surface>& surfaces() const;

 private:
  SegmentCheck checkVoxels(const Segment& segment, const CheckRequest& request) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hullmap::collision
