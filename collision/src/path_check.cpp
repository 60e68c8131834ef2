#include "hullmap/collision/path_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <octomap/OcTree.h>
#include <tbb/parallel_for.h>

#include "hullmap/collision/convex_distance.hpp"
#include "hullmap/mapper/error.hpp"

namespace hullmap::collision {
namespace {

/// First contact tolerance: 1e-3 of the segment or 1 mm, whichever is larger.
double contactTolerance(const Segment& segment) {
  const double length = (segment.b - segment.a).norm();
  return length > 0 ? std::max(1e-3, 1e-3 / length) : 1.0;
}

void checkRadius(double radius) {
  if (!(radius >= 0) || !std::isfinite(radius))
    throw Error("radius must be a finite number >= 0, got " + std::to_string(radius));
}

void checkSegment(const Segment& segment) {
  if (!segment.a.allFinite() || !segment.b.allFinite()) throw Error("segment has a non-finite coordinate");
}

template <typename CheckOne>
PathCheck checkWaypoints(const std::vector<Eigen::Vector3d>& waypoints, CheckOne&& check) {
  PathCheck path;
  if (waypoints.size() == 1) {
    path.segments.push_back(check(Segment{waypoints[0], waypoints[0]}));
  }
  for (std::size_t i = 0; i + 1 < waypoints.size(); ++i)
    path.segments.push_back(check(Segment{waypoints[i], waypoints[i + 1]}));
  for (std::size_t i = 0; i < path.segments.size(); ++i) {
    if (!path.segments[i].collides) continue;
    path.first_colliding_segment = i;
    const Eigen::Vector3d& a = waypoints[i];
    const Eigen::Vector3d& b = waypoints.size() == 1 ? a : waypoints[i + 1];
    path.first_contact = a + path.segments[i].t * (b - a);
    break;
  }
  return path;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Hull mode

struct HullChecker::Impl {
  std::vector<ConvexPolytope> polytopes;
  std::vector<int> ids;
  std::vector<std::shared_ptr<fcl::Convexd>> convexes;
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
  fcl::DynamicAABBTreeCollisionManagerd manager;
};

namespace {

/// State of one broadphase query: exact distances of the hulls the AABB tree could not rule out.
struct HullQuery {
  const std::vector<ConvexPolytope>* polytopes;
  Eigen::Vector3d a, b;
  double radius;
  double nearest = std::numeric_limits<double>::infinity();
  std::vector<std::size_t> touching;  ///< hulls within radius of the segment
};

bool visitHull(fcl::CollisionObjectd* tree_object, fcl::CollisionObjectd*, void* data, double& prune) {
  auto& q = *static_cast<HullQuery*>(data);
  const auto index = reinterpret_cast<std::size_t>(tree_object->getUserData());
  const double d = segmentPolytopeDistance(q.a, q.b, (*q.polytopes)[index]);
  if (d <= q.radius) q.touching.push_back(index);
  q.nearest = std::min(q.nearest, d);
  // Keep visiting every hull whose box is within the radius (all colliders are needed for the
  // first hit), else only those that could be nearer than the nearest so far.
  prune = std::max(q.nearest, q.radius) * (1 + 1e-12) + 1e-12;
  return false;
}

}  // namespace

HullChecker::HullChecker(const std::vector<clustering::Obstacle>& obstacles) : impl_(std::make_unique<Impl>()) {
  std::vector<fcl::CollisionObjectd*> registered;
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const auto& o = obstacles[i];
    const std::string what = "obstacle " + std::to_string(o.id);
    impl_->polytopes.push_back(ConvexPolytope::fromHull(o.hull, what));
    impl_->ids.push_back(o.id);
    auto vertices = std::make_shared<std::vector<Eigen::Vector3d>>(o.hull.vertices);
    auto faces = std::make_shared<std::vector<int>>();
    for (const auto& t : o.hull.triangles) faces->insert(faces->end(), {3, t[0], t[1], t[2]});
    std::shared_ptr<fcl::Convexd> convex;
    try {
      convex = std::make_shared<fcl::Convexd>(vertices, int(o.hull.triangles.size()), faces, true);
    } catch (const std::exception& e) {
      throw Error(what + ": FCL rejects the hull: " + e.what());
    }
    convex->computeLocalAABB();
    impl_->convexes.push_back(convex);
    auto object = std::make_unique<fcl::CollisionObjectd>(convex);
    object->setUserData(reinterpret_cast<void*>(i));
    object->computeAABB();
    registered.push_back(object.get());
    impl_->objects.push_back(std::move(object));
  }
  impl_->manager.registerObjects(registered);
  impl_->manager.setup();
}

HullChecker::~HullChecker() = default;
HullChecker::HullChecker(HullChecker&&) noexcept = default;
HullChecker& HullChecker::operator=(HullChecker&&) noexcept = default;

SegmentCheck HullChecker::check(const Segment& segment, double radius) const {
  checkRadius(radius);
  checkSegment(segment);
  SegmentCheck result;
  if (impl_->polytopes.empty()) {
    result.clearance = std::numeric_limits<double>::infinity();
    return result;
  }
  // The query object is the segment's box; the radius enters through the exact distances.
  const Eigen::Vector3d lo = segment.a.cwiseMin(segment.b), hi = segment.a.cwiseMax(segment.b);
  auto box = std::make_shared<fcl::Boxd>(hi - lo);
  fcl::Transform3d pose = fcl::Transform3d::Identity();
  pose.translation() = 0.5 * (lo + hi);
  fcl::CollisionObjectd query(box, pose);
  query.computeAABB();
  HullQuery q{&impl_->polytopes, segment.a, segment.b, radius, std::numeric_limits<double>::infinity(), {}};
  impl_->manager.distance(&query, &q, visitHull);

  if (q.touching.empty()) {
    result.clearance = q.nearest - radius;
    return result;
  }
  result.collides = true;
  result.clearance = 0.0;
  const double tolerance = contactTolerance(segment);
  std::sort(q.touching.begin(), q.touching.end());
  for (const std::size_t index : q.touching) {
    const ConvexPolytope& p = impl_->polytopes[index];
    // A later hull can only be first if the sweep up to the current first contact touches it.
    const Eigen::Vector3d end = segment.a + result.t * (segment.b - segment.a);
    if (result.obstacle >= 0 && segmentPolytopeDistance(segment.a, end, p) > radius) continue;
    const double t = firstContact(segment.a, end, p, radius, tolerance / std::max(result.t, 1e-300));
    if (t < 0) continue;
    const double t_segment = t * result.t;
    if (result.obstacle < 0 || t_segment < result.t) {
      result.t = t_segment;
      result.obstacle = impl_->ids[index];
    }
  }
  return result;
}

PathCheck HullChecker::checkPath(const std::vector<Eigen::Vector3d>& waypoints, double radius) const {
  return checkWaypoints(waypoints, [&](const Segment& s) { return check(s, radius); });
}

std::vector<SegmentCheck> HullChecker::checkBatch(const std::vector<Segment>& segments, double radius) const {
  checkRadius(radius);
  std::vector<SegmentCheck> results(segments.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, segments.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) results[i] = check(segments[i], radius);
                    });
  return results;
}

// ---------------------------------------------------------------------------------------------
// Octree mode

struct OctreeChecker::Impl {
  std::shared_ptr<const octomap::OcTree> tree;
  std::shared_ptr<fcl::OcTreed> geometry;
  std::unique_ptr<fcl::CollisionObjectd> object;
};

namespace {

/// The sphere of `radius` swept from a to a + t (b - a): an FCL capsule (a sphere when t = 0).
fcl::CollisionObjectd sweptSphere(const Segment& segment, double t, double radius) {
  const Eigen::Vector3d d = t * (segment.b - segment.a);
  const double length = d.norm();
  fcl::Transform3d pose = fcl::Transform3d::Identity();
  pose.translation() = segment.a + 0.5 * d;
  // FCL's collide/distance treat radius 0 as no volume; a hair of radius keeps a line a line.
  const double r = std::max(radius, 1e-9);
  if (length <= 0) return fcl::CollisionObjectd(std::make_shared<fcl::Sphered>(r), pose);
  pose.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), d / length).toRotationMatrix();
  return fcl::CollisionObjectd(std::make_shared<fcl::Capsuled>(r, length), pose);
}

}  // namespace

OctreeChecker::OctreeChecker(const octomap::OcTree& tree) : impl_(std::make_unique<Impl>()) {
  impl_->tree = std::make_shared<const octomap::OcTree>(tree);
  impl_->geometry = std::make_shared<fcl::OcTreed>(impl_->tree);
  impl_->object = std::make_unique<fcl::CollisionObjectd>(impl_->geometry);
  impl_->object->computeAABB();
}

OctreeChecker::~OctreeChecker() = default;
OctreeChecker::OctreeChecker(OctreeChecker&&) noexcept = default;
OctreeChecker& OctreeChecker::operator=(OctreeChecker&&) noexcept = default;

SegmentCheck OctreeChecker::check(const Segment& segment, double radius) const {
  checkRadius(radius);
  checkSegment(segment);
  SegmentCheck result;
  auto collidesUpTo = [&](double t) {
    fcl::CollisionObjectd sweep = sweptSphere(segment, t, radius);
    fcl::CollisionRequestd request;
    fcl::CollisionResultd answer;
    fcl::collide(&sweep, impl_->object.get(), request, answer);
    return answer.isCollision();
  };
  if (!collidesUpTo(1.0)) {
    fcl::CollisionObjectd sweep = sweptSphere(segment, 1.0, radius);
    fcl::DistanceRequestd request;
    fcl::DistanceResultd answer;
    fcl::distance(&sweep, impl_->object.get(), request, answer);
    result.clearance = answer.min_distance;
    return result;
  }
  result.collides = true;
  result.clearance = 0.0;
  if (collidesUpTo(0.0)) {
    result.t = 0.0;
    return result;
  }
  double lo = 0, hi = 1;
  const double tolerance = contactTolerance(segment);
  while (hi - lo > tolerance) {
    const double mid = 0.5 * (lo + hi);
    (collidesUpTo(mid) ? hi : lo) = mid;
  }
  result.t = hi;
  return result;
}

PathCheck OctreeChecker::checkPath(const std::vector<Eigen::Vector3d>& waypoints, double radius) const {
  return checkWaypoints(waypoints, [&](const Segment& s) { return check(s, radius); });
}

}  // namespace hullmap::collision
