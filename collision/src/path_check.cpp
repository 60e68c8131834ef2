#include "hullmap/collision/path_check.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <octomap/OcTree.h>
#include <tbb/parallel_for.h>

#include "convex_distance_detail.hpp"
#include "height_field_sweep.hpp"
#include "hullmap/collision/convex_distance.hpp"
#include "hullmap/collision/fcl_obstacles.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::collision {
namespace {

/// The request's contact tolerance as a fraction of the segment: 1e-3 of the segment or
/// contact_tolerance map units, whichever is larger.
double contactTolerance(const Segment& segment, const CheckRequest& request) {
  const double length = (segment.b - segment.a).norm();
  return length > 0 ? std::max(1e-3, request.contact_tolerance / length) : 1.0;
}

void checkRequest(const CheckRequest& request) {
  if (!(request.radius >= 0) || !std::isfinite(request.radius))
    throw Error::inParameter("radius", "must be a finite number >= 0, got " + std::to_string(request.radius));
  if (!(request.contact_tolerance > 0) || !std::isfinite(request.contact_tolerance))
    throw Error::inParameter("contact_tolerance",
                             "must be a finite number > 0, got " + std::to_string(request.contact_tolerance));
}

void checkSegment(const Segment& segment) {
  if (!segment.a.allFinite() || !segment.b.allFinite()) throw Error("segment has a non-finite coordinate");
}

void checkSurfaces(const std::vector<Surface>& surfaces) {
  for (const Surface& h : surfaces) {
    const std::string name = h.name.empty() ? std::string("a surface") : "\"" + h.name + "\"";
    if (h.field) {
      if (!h.field->valid())
        throw Error::inParameter("surfaces", name +
                                                 ": the height field needs a finite step > 0, a finite origin and "
                                                 "nx * ny >= 1 finite heights");
      continue;
    }
    if (!h.normal.allFinite() || std::abs(h.normal.norm() - 1.0) > 1e-9)
      throw Error::inParameter("surfaces", name + ": the normal must be a finite unit vector");
    if (!std::isfinite(h.offset)) throw Error::inParameter("surfaces", name + ": the offset must be finite");
  }
}

/// The capsule against one half-space, inputs already validated: the distance to the solid is
/// linear along the segment, so its minimum is at an end and the first contact is where it falls
/// to the radius.
SegmentCheck sweepPlane(const Segment& segment, double radius, const Surface& surface) {
  SegmentCheck result;
  const double da = surface.distance(segment.a), db = surface.distance(segment.b);
  const double nearest = std::min(da, db);
  if (nearest > radius) {
    result.clearance = nearest - radius;
    return result;
  }
  result.collides = true;
  result.clearance = 0.0;
  result.surface = surface.name;
  // da > radius >= db here unless the start is already within radius, so da - db > 0.
  result.t = da <= radius ? 0.0 : std::clamp((da - radius) / (da - db), 0.0, 1.0);
  return result;
}

/// One surface, inputs validated: a plane exactly, a height field to `t_tolerance`.
SegmentCheck sweepSurface(const Segment& segment, double radius, const Surface& surface, double t_tolerance) {
  return surface.field ? detail::sweepHeightField(segment, radius, surface, t_tolerance)
                       : sweepPlane(segment, radius, surface);
}

/// Folds the surfaces into a check against the other obstacles: the earliest contact wins (a
/// hull or voxel on a tie), and a clear segment's clearance is the least of all.
void addSurfaces(const Segment& segment, const CheckRequest& request, const std::vector<Surface>& surfaces,
                 SegmentCheck& result) {
  for (const Surface& surface : surfaces) {
    SegmentCheck s = sweepSurface(segment, request.radius, surface, contactTolerance(segment, request));
    if (s.collides) {
      if (!result.collides || s.t < result.t) result = std::move(s);
    } else if (!result.collides) {
      result.clearance = std::min(result.clearance, s.clearance);
    }
  }
}

template <typename CheckOne>
PathCheck checkWaypoints(const std::vector<Eigen::Vector3d>& waypoints, CheckOne&& check) {
  PathCheck path;
  std::vector<Segment> legs;
  if (waypoints.size() == 1) legs.push_back(Segment{waypoints[0], waypoints[0]});
  for (std::size_t i = 0; i + 1 < waypoints.size(); ++i) legs.push_back(Segment{waypoints[i], waypoints[i + 1]});
  path.segments = check(legs);
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

SegmentCheck checkSurface(const Segment& segment, double radius, const Surface& surface, double contact_tolerance) {
  const CheckRequest request{radius, contact_tolerance};
  checkRequest(request);
  checkSegment(segment);
  checkSurfaces({surface});
  return sweepSurface(segment, radius, surface, contactTolerance(segment, request));
}

// ---------------------------------------------------------------------------------------------
// Hull mode

namespace {

/// The segment a + t d, t in [0, 1], with the reciprocals of d for slab tests.
struct SegmentRay {
  Eigen::Vector3d a, d, inverse;
  SegmentRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to) : a(from), d(to - from) {
    for (int k = 0; k < 3; ++k) inverse[k] = d[k] != 0 ? 1 / d[k] : 0.0;
  }

  /// Whether the segment may come within `reach` of the box; false proves its distance is more.
  /// Clips the segment to the box grown by `reach` in every coordinate (where its max-norm
  /// distance is <= reach), then takes the gap between the clipped piece's box and the box.
  bool near(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double reach) const {
    double t0 = 0, t1 = 1;
    for (int k = 0; k < 3; ++k) {
      const double low = lo[k] - reach - a[k], high = hi[k] + reach - a[k];
      if (d[k] == 0) {
        if (low > 0 || high < 0) return false;
        continue;
      }
      double ta = low * inverse[k], tb = high * inverse[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    if (t0 > t1) return false;
    const Eigen::Vector3d p0 = a + t0 * d, p1 = a + t1 * d;
    const Eigen::Vector3d gap = (lo - p0.cwiseMax(p1)).cwiseMax(p0.cwiseMin(p1) - hi).cwiseMax(0.0);
    return gap.squaredNorm() <= reach * reach;
  }
};

/// A bound grown by a hair, so that rounding in the box tests never drops a hull at the bound.
double widen(double bound) { return bound * (1 + 1e-12) + 1e-12; }

/// Hulls within radius of the segment (few: usually none or one), without allocating for those.
class TouchingHulls {
 public:
  /// Entries are (lower bound on the first contact, hull); the bound is filled in later.
  void push(int hull) {
    if (size_ < kInline) {
      inline_[size_] = {0.0, hull};
    } else {
      if (spill_.empty()) spill_.assign(inline_.begin(), inline_.end());
      spill_.push_back({0.0, hull});
    }
    ++size_;
  }
  std::size_t size() const { return size_; }
  std::pair<double, int>* begin() { return spill_.empty() ? inline_.data() : spill_.data(); }
  std::pair<double, int>* end() { return begin() + size_; }

 private:
  static constexpr std::size_t kInline = 8;
  std::array<std::pair<double, int>, kInline> inline_{};
  std::vector<std::pair<double, int>> spill_;
  std::size_t size_ = 0;
};

}  // namespace

struct HullChecker::Impl {
  Impl(const std::vector<hulls::Obstacle>& obstacles, std::vector<Surface> given)
      : fcl(obstacles), surfaces(std::move(given)) {
    checkSurfaces(surfaces);
    for (std::size_t i = 0; i < fcl.size(); ++i) {
      ids.push_back(fcl.source(i).id);
      parts.push_back(fcl.source(i).part);
    }
  }
  /// The check against the hulls alone.
  SegmentCheck checkHulls(const Segment& segment, const CheckRequest& request) const;

  FclObstacles fcl;
  std::vector<Surface> surfaces;
  std::vector<int> ids;    ///< per FCL object: its obstacle's id
  std::vector<int> parts;  ///< per FCL object: its part index (-1: whole hull)
};

namespace {

/// The query object of FCL's broadphase: the segment's bounding box, reused by each thread (FCL's
/// manager needs an object, and a fresh one per check costs two allocations).
class SegmentBox {
 public:
  fcl::CollisionObjectd& place(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    box_->side = hi - lo;
    // What Box::computeLocalAABB gives for an axis-aligned box, without its general rotated-box path.
    box_->aabb_local = fcl::AABBd(-0.5 * box_->side, 0.5 * box_->side);
    object_.setTranslation(0.5 * (lo + hi));
    object_.computeAABB();
    return object_;
  }

 private:
  std::shared_ptr<fcl::Boxd> box_ = std::make_shared<fcl::Boxd>(1.0, 1.0, 1.0);
  fcl::CollisionObjectd object_{box_};
};

/// One check's state in FCL's broadphase traversal.
struct HullQuery {
  const FclObstacles* obstacles;
  const Eigen::Vector3d* a;
  const Eigen::Vector3d* b;
  const SegmentRay* ray;
  double radius;
  double nearest = std::numeric_limits<double>::infinity();
  double reach = std::numeric_limits<double>::infinity();  ///< max(nearest, radius), widened
  TouchingHulls touching;
};

/// FCL visits the hulls whose boxes are within `prune` of the segment's box, nearer boxes first.
/// Every hull within radius is kept (all are needed for the first contact), and else the nearest
/// one; hulls are computed exactly only where it matters: one within radius is touching whatever
/// its distance, one proven beyond the reach is neither touching nor the nearest.
bool visitHull(fcl::CollisionObjectd* object, fcl::CollisionObjectd*, void* data, double& prune) {
  auto& q = *static_cast<HullQuery*>(data);
  const std::size_t hull = FclObstacles::indexOf(*object);
  const ConvexPolytope& polytope = q.obstacles->polytope(hull);
  if (q.ray->near(polytope.aabb_min, polytope.aabb_max, q.reach)) {
    const detail::DistanceCertificate c = detail::certifiedDistance(*q.a, *q.b, polytope, q.radius, q.reach);
    if (c.upper <= q.radius) q.touching.push(int(hull));
    if (c.lower <= q.reach && c.upper < q.nearest) {
      q.nearest = c.upper;
      q.reach = widen(std::max(q.nearest, q.radius));
    }
  }
  prune = q.reach;
  return false;
}

}  // namespace

HullChecker::HullChecker(const std::vector<hulls::Obstacle>& obstacles, std::vector<Surface> surfaces)
    : impl_(std::make_unique<Impl>(obstacles, std::move(surfaces))) {}

HullChecker::~HullChecker() = default;
HullChecker::HullChecker(HullChecker&&) noexcept = default;
HullChecker& HullChecker::operator=(HullChecker&&) noexcept = default;

const std::vector<Surface>& HullChecker::surfaces() const { return impl_->surfaces; }

SegmentCheck HullChecker::check(const Segment& segment, const CheckRequest& request) const {
  checkRequest(request);
  checkSegment(segment);
  SegmentCheck result = impl_->checkHulls(segment, request);
  addSurfaces(segment, request, impl_->surfaces, result);
  return result;
}

SegmentCheck HullChecker::Impl::checkHulls(const Segment& segment, const CheckRequest& request) const {
  const double radius = request.radius;
  SegmentCheck result;
  const FclObstacles& obstacles = fcl;
  if (obstacles.size() == 0) {
    result.clearance = std::numeric_limits<double>::infinity();
    return result;
  }
  const Eigen::Vector3d& a = segment.a;
  const SegmentRay ray(a, segment.b);
  thread_local SegmentBox query;
  HullQuery q{&obstacles,
              &segment.a,
              &segment.b,
              &ray,
              radius,
              std::numeric_limits<double>::infinity(),
              std::numeric_limits<double>::infinity(),
              {}};
  obstacles.manager().distance(&query.place(a.cwiseMin(segment.b), a.cwiseMax(segment.b)), &q, visitHull);
  const double nearest = q.nearest;
  TouchingHulls& touching = q.touching;

  if (touching.size() == 0) {
    result.clearance = nearest - radius;
    return result;
  }
  result.collides = true;
  result.clearance = 0.0;
  const double tolerance = contactTolerance(segment, request);
  // Hulls in the order the sweep can first reach them; one that cannot be reached before the
  // first contact found so far is not computed.
  for (auto& [bound, hull] : touching) {
    bound = detail::contactLowerBound(a, segment.b, obstacles.polytope(std::size_t(hull)), radius);
    if (bound > 1.0) bound = 0.0;  // rounding only: the hull is within radius of the segment
  }
  std::sort(touching.begin(), touching.end());
  double first = std::numeric_limits<double>::infinity();
  int first_hull = -1;
  for (const auto& [bound, hull] : touching) {
    if (bound > first) break;
    const double t =
        detail::firstContactTouching(a, segment.b, obstacles.polytope(std::size_t(hull)), radius, tolerance, bound);
    if (t < first || (t == first && hull < first_hull)) {
      first = t;
      first_hull = hull;
    }
  }
  result.t = first;
  result.obstacle = ids[std::size_t(first_hull)];
  result.part = parts[std::size_t(first_hull)];
  return result;
}

PathCheck HullChecker::checkPath(const std::vector<Eigen::Vector3d>& waypoints, const CheckRequest& request) const {
  return checkWaypoints(waypoints, [&](const std::vector<Segment>& legs) { return checkBatch(legs, request); });
}

std::vector<SegmentCheck> HullChecker::checkBatch(const std::vector<Segment>& segments,
                                                  const CheckRequest& request) const {
  checkRequest(request);
  std::vector<SegmentCheck> results(segments.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, segments.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i)
                        results[i] = check(segments[i], request);
                    });
  return results;
}

// ---------------------------------------------------------------------------------------------
// Octree mode

struct OctreeChecker::Impl {
  std::vector<Surface> surfaces;
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

OctreeChecker::OctreeChecker(const octomap::OcTree& tree, std::vector<Surface> surfaces)
    : impl_(std::make_unique<Impl>()) {
  checkSurfaces(surfaces);
  impl_->surfaces = std::move(surfaces);
  impl_->tree = std::make_shared<const octomap::OcTree>(tree);
  impl_->geometry = std::make_shared<fcl::OcTreed>(impl_->tree);
  impl_->object = std::make_unique<fcl::CollisionObjectd>(impl_->geometry);
  impl_->object->computeAABB();
}

OctreeChecker::~OctreeChecker() = default;
OctreeChecker::OctreeChecker(OctreeChecker&&) noexcept = default;
OctreeChecker& OctreeChecker::operator=(OctreeChecker&&) noexcept = default;

const std::vector<Surface>& OctreeChecker::surfaces() const { return impl_->surfaces; }

SegmentCheck OctreeChecker::check(const Segment& segment, const CheckRequest& request) const {
  checkRequest(request);
  checkSegment(segment);
  SegmentCheck result = checkVoxels(segment, request);
  addSurfaces(segment, request, impl_->surfaces, result);
  return result;
}

SegmentCheck OctreeChecker::checkVoxels(const Segment& segment, const CheckRequest& request) const {
  const double radius = request.radius;
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
  const double tolerance = contactTolerance(segment, request);
  while (hi - lo > tolerance) {
    const double mid = 0.5 * (lo + hi);
    (collidesUpTo(mid) ? hi : lo) = mid;
  }
  result.t = hi;
  return result;
}

PathCheck OctreeChecker::checkPath(const std::vector<Eigen::Vector3d>& waypoints, const CheckRequest& request) const {
  return checkWaypoints(waypoints, [&](const std::vector<Segment>& legs) {
    std::vector<SegmentCheck> results;
    for (const auto& s : legs) results.push_back(check(s, request));
    return results;
  });
}

}  // namespace hullmap::collision
