#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/narrowphase/collision_object.h>

#include "hullmap/collision/convex_distance.hpp"
#include "hullmap/hulls/obstacles.hpp"

namespace hullmap::collision {

/// Which hull an object of FclObstacles is: part `part` of the obstacle whose id
/// (hulls::Obstacle::id) is `id`, or (part -1) the whole hull of an obstacle that has no parts.
struct HullSource {
  int id = 0;
  int part = -1;
};

/// The obstacles as FCL collision objects, for planners that query FCL themselves: one object per
/// convex part of an obstacle that has parts (clustering/convex_parts.hpp), else one for its whole
/// hull (so without parts, object i is obstacles[i]); each hull an
/// `fcl::Convexd` (triangles as faces, outward), validated twice — hullmap's check that it is
/// closed, convex and of positive volume, then FCL's own topology check (`throw_if_invalid`) — at
/// the identity pose (hull vertices are in the z-up map frame, map units), all registered in one
/// `fcl::DynamicAABBTreeCollisionManagerd`, already set up. An FCL callback names the obstacle (by
/// its id) and part an object stands for with source(indexOf(object)), as HullChecker's results do.
/// Each hull is kept as a ConvexPolytope too.
///
/// HullChecker uses this manager as its broadphase; its answers come from hullmap's certified
/// segment-hull distance (convex_distance.hpp), not FCL's narrowphase (why: docs/LIBRARY.md,
/// "FCL's own narrowphase, measured").
///
/// Immutable after construction: the const queries of FCL's manager (collide, distance against one
/// object) may run from several threads at once. Movable, not copyable (the manager holds the
/// objects' addresses, which a move keeps).
class FclObstacles {
 public:
  /// Throws hullmap::Error naming the obstacle id (and part) when a hull is invalid.
  explicit FclObstacles(const std::vector<hulls::Obstacle>& obstacles);
  ~FclObstacles();
  FclObstacles(FclObstacles&&) noexcept;
  FclObstacles& operator=(FclObstacles&&) noexcept;
  FclObstacles(const FclObstacles&) = delete;
  FclObstacles& operator=(const FclObstacles&) = delete;

  /// Every obstacle's object, set up for queries.
  const fcl::DynamicAABBTreeCollisionManagerd& manager() const { return *manager_; }

  /// Number of objects (hulls).
  std::size_t size() const { return objects_.size(); }
  /// Object i.
  const fcl::CollisionObjectd& object(std::size_t i) const { return *objects_[i]; }

  /// The hull of object i for hullmap's exact queries (the same vertices as object(i)).
  const ConvexPolytope& polytope(std::size_t i) const { return polytopes_[i]; }

  /// The obstacle (by id) and part of object i.
  const HullSource& source(std::size_t i) const { return sources_[i]; }

  /// The id (hulls::Obstacle::id) of the obstacle an object this class made stands for.
  int idOf(const fcl::CollisionObjectd& object) const { return sources_[indexOf(object)].id; }

  /// Position of an object this class made among object(i) and polytope(i) (the user data FCL carries).
  static std::size_t indexOf(const fcl::CollisionObjectd& object) {
    return reinterpret_cast<std::size_t>(object.getUserData());
  }

 private:
  std::vector<ConvexPolytope> polytopes_;
  std::vector<HullSource> sources_;
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects_;
  std::unique_ptr<fcl::DynamicAABBTreeCollisionManagerd> manager_;
};

}  // namespace hullmap::collision
