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

/// Result for one segment swept by a sphere of radius r (a capsule).
struct SegmentCheck {
  bool collides = false;
  int obstacle = -1;        ///< id of the obstacle hit first (-1: none)
  int part = -1;            ///< index of its part hit first (-1: none, or an obstacle without parts)
  double t = 1.0;           ///< first contact as a fraction of the segment (valid when collides)
  double clearance = 0.0;   ///< min distance to any obstacle minus r; 0 when colliding
};

struct PathCheck {
  std::vector<SegmentCheck> segments;
  std::optional<std::size_t> first_colliding_segment;
  std::optional<Eigen::Vector3d> first_contact;   ///< point on the path
};

/// Hull mode: the obstacles' convex hulls (one per convex part when an obstacle has parts) as FCL objects in FCL's broadphase manager (FclObstacles);
/// every answer from certified segment-hull distances (convex_distance.hpp), the first contact
/// bracketed as firstContact does. Throws hullmap::Error on an invalid hull (naming its id).
/// Thread-safe for concurrent checks after construction.
class HullChecker {
 public:
  explicit HullChecker(const std::vector<clustering::Obstacle>& obstacles);
  ~HullChecker();
  HullChecker(HullChecker&&) noexcept;
  HullChecker& operator=(HullChecker&&) noexcept;

  SegmentCheck check(const Segment& segment, double radius) const;
  PathCheck checkPath(const std::vector<Eigen::Vector3d>& waypoints, double radius) const;
  std::vector<SegmentCheck> checkBatch(const std::vector<Segment>& segments, double radius) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Octree mode: the same questions against every occupied voxel of the map (FCL's OcTree).
class OctreeChecker {
 public:
  explicit OctreeChecker(const octomap::OcTree& tree);
  ~OctreeChecker();
  OctreeChecker(OctreeChecker&&) noexcept;
  OctreeChecker& operator=(OctreeChecker&&) noexcept;

  SegmentCheck check(const Segment& segment, double radius) const;
  PathCheck checkPath(const std::vector<Eigen::Vector3d>& waypoints, double radius) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hullmap::collision
