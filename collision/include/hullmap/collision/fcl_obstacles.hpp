#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/narrowphase/collision_object.h>

#include "hullmap/clustering/obstacles.hpp"
#include "hullmap/collision/convex_distance.hpp"

namespace hullmap::collision {

/// The obstacles as FCL collision objects, for planners that query FCL themselves: each hull an
/// `fcl::Convexd` (triangles as faces, outward), validated twice — hullmap's check that it is
/// closed, convex and of positive volume, then FCL's own topology check (`throw_if_invalid`) — at
/// the identity pose (hull vertices are in the z-up map frame, map units), all registered in one
/// `fcl::DynamicAABBTreeCollisionManagerd`, already set up. An FCL callback names the obstacle an
/// object stands for by its id (idOf), as HullChecker's results do. Each hull is kept as a
/// ConvexPolytope too.
///
/// HullChecker uses this manager as its broadphase. It does not take its answers from FCL's
/// narrowphase on `Convex` (GJK/EPA distances that are not exact, and a continuous collision that
/// samples poses; test/collision_distance.cpp measures how far they are off): it computes them with
/// hullmap's certified segment-hull distance (convex_distance.hpp).
///
/// Immutable after construction: the const queries of FCL's manager (collide, distance against one
/// object) may run from several threads at once. Movable, not copyable (the manager holds the
/// objects' addresses, which a move keeps).
class FclObstacles {
 public:
  /// Throws hullmap::Error naming the obstacle id when a hull is invalid.
  explicit FclObstacles(const std::vector<clustering::Obstacle>& obstacles);
  ~FclObstacles();
  FclObstacles(FclObstacles&&) noexcept;
  FclObstacles& operator=(FclObstacles&&) noexcept;
  FclObstacles(const FclObstacles&) = delete;
  FclObstacles& operator=(const FclObstacles&) = delete;

  /// Every obstacle's object, set up for queries.
  const fcl::DynamicAABBTreeCollisionManagerd& manager() const { return *manager_; }

  std::size_t size() const { return objects_.size(); }
  /// The object of obstacles[i].
  const fcl::CollisionObjectd& object(std::size_t i) const { return *objects_[i]; }

  /// The hull of obstacles[i] for hullmap's exact queries (the same vertices as object(i)).
  const ConvexPolytope& polytope(std::size_t i) const { return polytopes_[i]; }

  /// The id (clustering::Obstacle::id) of the obstacle an object this class made stands for.
  int idOf(const fcl::CollisionObjectd& object) const { return ids_[indexOf(object)]; }

  /// Position of an object this class made among object(i) and polytope(i) (the user data FCL carries).
  static std::size_t indexOf(const fcl::CollisionObjectd& object) {
    return reinterpret_cast<std::size_t>(object.getUserData());
  }

 private:
  std::vector<int> ids_;
  std::vector<ConvexPolytope> polytopes_;
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects_;
  std::unique_ptr<fcl::DynamicAABBTreeCollisionManagerd> manager_;
};

}  // namespace hullmap::collision
