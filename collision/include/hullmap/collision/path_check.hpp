#pragma once

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/obstacles.hpp"

namespace octomap { class OcTree; }

namespace hullmap::collision {

/// A straight segment of a path, map frame.
struct Segment {
  Eigen::Vector3d a;
  Eigen::Vector3d b;
};

/// Default of CheckRequest::contact_tolerance, map units.
inline constexpr double kContactTolerance = 1e-3;

/// How a check is asked, in the manner of FCL's request structs.
struct CheckRequest {
  double radius = 0.0;  ///< radius of the sphere swept along the segment (the drone), map units, >= 0
  /// How far after the true first contact the reported one may lie, map units along the segment:
  /// the reported t is at or after the true first contact, by at most
  /// max(contact_tolerance, 1e-3 * segment length). Must be > 0.
  double contact_tolerance = kContactTolerance;
};

/// Result for one segment swept by a sphere of radius r (a capsule).
struct SegmentCheck {
  bool collides = false;
  int obstacle = -1;        ///< HullChecker: id (Obstacle::id) of the obstacle hit first; -1 when clear
                            ///< or in octree mode (voxels have no id)
  int part = -1;            ///< HullChecker: index of that obstacle's convex part hit first; -1 when
                            ///< clear, in octree mode, or for an obstacle without parts
  double t = 1.0;           ///< first contact as a fraction of the segment (valid when collides)
  double clearance = 0.0;   ///< min distance to any obstacle minus r, map units; 0 when colliding
};

/// Result for a path of waypoints: one SegmentCheck per leg (one for a single waypoint).
struct PathCheck {
  std::vector<SegmentCheck> segments;
  std::optional<std::size_t> first_colliding_segment;
  std::optional<Eigen::Vector3d> first_contact;   ///< point on the path, map frame
};

/// Hull mode: the obstacles' convex hulls (one per convex part when an obstacle has parts) as FCL objects in FCL's broadphase manager (FclObstacles);
/// every answer from certified segment-hull distances (convex_distance.hpp), the first contact
/// bracketed as firstContact does.
///
/// Coordinates in the obstacles' frame (hullmap's z-up map frame), map units. The constructor
/// copies the obstacles' hulls (as ConvexPolytope and FCL objects) and their ids; the vector given
/// may go away after it. Throws hullmap::Error on an invalid hull (naming its id); the checks throw
/// hullmap::Error naming `radius` (negative or not finite) or `contact_tolerance` (not > 0), or on a
/// non-finite coordinate. Immutable after construction: concurrent checks from several threads are
/// safe; checkBatch and checkPath themselves use all cores (TBB). Movable, not copyable.
class HullChecker {
 public:
  explicit HullChecker(const std::vector<clustering::Obstacle>& obstacles);
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

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Octree mode: the same questions against every occupied voxel of the map (FCL's OcTree and
/// FCL's capsule-box narrowphase, the first contact found by bisection on the swept prefix to the
/// request's tolerance). SegmentCheck::obstacle is always -1. The constructor copies the tree.
/// Units, frame, errors and thread safety as HullChecker's. Movable, not copyable.
class OctreeChecker {
 public:
  explicit OctreeChecker(const octomap::OcTree& tree);
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

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hullmap::collision
