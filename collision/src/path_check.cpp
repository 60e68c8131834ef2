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
#include <fcl/geometry/shape/capsule.h>
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

namespace {

/// A node of the bounding-box tree over the hulls: a leaf holds one hull.
struct BoxNode {
  Eigen::Array4d lo, hi;  ///< x, y, z and a zero, so that box gaps take whole SIMD registers
  int left = -1;  ///< children (leaf when left < 0)
  int right = -1;
  int hull = -1;  ///< at a leaf
};

/// Median split on the longest axis of the boxes' centres: depth <= ceil(log2(hulls)) + 1.
int buildTree(std::vector<BoxNode>& nodes, std::vector<int>& hulls, std::size_t begin, std::size_t end,
              const std::vector<ConvexPolytope>& polytopes) {
  const int index = int(nodes.size());
  nodes.emplace_back();
  const ConvexPolytope& first = polytopes[std::size_t(hulls[begin])];
  Eigen::Vector3d lo = first.aabb_min, hi = first.aabb_max;
  Eigen::Vector3d c_lo = lo + hi, c_hi = lo + hi;
  for (std::size_t i = begin + 1; i < end; ++i) {
    const ConvexPolytope& p = polytopes[std::size_t(hulls[i])];
    lo = lo.cwiseMin(p.aabb_min);
    hi = hi.cwiseMax(p.aabb_max);
    c_lo = c_lo.cwiseMin(p.aabb_min + p.aabb_max);
    c_hi = c_hi.cwiseMax(p.aabb_min + p.aabb_max);
  }
  nodes[std::size_t(index)].lo << lo.array(), 0.0;
  nodes[std::size_t(index)].hi << hi.array(), 0.0;
  if (end - begin == 1) {
    nodes[std::size_t(index)].hull = hulls[begin];
    return index;
  }
  int axis = 0;
  (c_hi - c_lo).maxCoeff(&axis);
  const std::size_t mid = begin + (end - begin) / 2;
  std::nth_element(hulls.begin() + std::ptrdiff_t(begin), hulls.begin() + std::ptrdiff_t(mid),
                   hulls.begin() + std::ptrdiff_t(end), [&](int x, int y) {
                     const ConvexPolytope& p = polytopes[std::size_t(x)];
                     const ConvexPolytope& q = polytopes[std::size_t(y)];
                     const double cx = p.aabb_min[axis] + p.aabb_max[axis], cy = q.aabb_min[axis] + q.aabb_max[axis];
                     return cx < cy || (cx == cy && x < y);
                   });
  const int left = buildTree(nodes, hulls, begin, mid, polytopes);
  const int right = buildTree(nodes, hulls, mid, end, polytopes);
  nodes[std::size_t(index)].left = left;
  nodes[std::size_t(index)].right = right;
  return index;
}

/// Squared distance between two axis-aligned boxes (fourth coordinates zero).
inline double boxGapSquared(const Eigen::Array4d& lo1, const Eigen::Array4d& hi1, const Eigen::Array4d& lo2,
                            const Eigen::Array4d& hi2) {
  return (lo2 - hi1).max(lo1 - hi2).max(0.0).square().sum();
}

/// The segment a + t d, t in [0, 1], with the reciprocals of d for slab tests.
struct SegmentRay {
  Eigen::Vector3d a, d, inverse;
  SegmentRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to) : a(from), d(to - from) {
    for (int k = 0; k < 3; ++k) inverse[k] = d[k] != 0 ? 1 / d[k] : 0.0;
  }

  /// Whether the segment may come within `reach` of the box; false proves its distance is more.
  /// Clips the segment to the box grown by `reach` in every coordinate (where its max-norm
  /// distance is <= reach), then takes the gap between the clipped piece's box and the box.
  bool near(const Eigen::Array4d& lo, const Eigen::Array4d& hi, double reach) const {
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
    Eigen::Array4d piece_lo, piece_hi;
    piece_lo << p0.cwiseMin(p1).array(), 0.0;
    piece_hi << p0.cwiseMax(p1).array(), 0.0;
    return boxGapSquared(piece_lo, piece_hi, lo, hi) <= reach * reach;
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
  std::vector<ConvexPolytope> polytopes;
  std::vector<int> ids;
  std::vector<BoxNode> nodes;  ///< root first
};

HullChecker::HullChecker(const std::vector<clustering::Obstacle>& obstacles) : impl_(std::make_unique<Impl>()) {
  for (const auto& o : obstacles) {
    impl_->polytopes.push_back(ConvexPolytope::fromHull(o.hull, "obstacle " + std::to_string(o.id)));
    impl_->ids.push_back(o.id);
  }
  if (obstacles.empty()) return;
  std::vector<int> hulls(obstacles.size());
  for (std::size_t i = 0; i < hulls.size(); ++i) hulls[i] = int(i);
  impl_->nodes.reserve(2 * hulls.size());
  buildTree(impl_->nodes, hulls, 0, hulls.size(), impl_->polytopes);
}

HullChecker::~HullChecker() = default;
HullChecker::HullChecker(HullChecker&&) noexcept = default;
HullChecker& HullChecker::operator=(HullChecker&&) noexcept = default;

SegmentCheck HullChecker::check(const Segment& segment, double radius) const {
  checkRadius(radius);
  checkSegment(segment);
  SegmentCheck result;
  const auto& polytopes = impl_->polytopes;
  const auto& nodes = impl_->nodes;
  if (polytopes.empty()) {
    result.clearance = std::numeric_limits<double>::infinity();
    return result;
  }
  const Eigen::Vector3d& a = segment.a;
  const SegmentRay ray(a, segment.b);
  Eigen::Array4d lo, hi;
  lo << a.cwiseMin(segment.b).array(), 0.0;
  hi << a.cwiseMax(segment.b).array(), 0.0;

  // Every hull within radius (all are needed for the first contact), and else the nearest one:
  // depth first, the nearer box first, pruning boxes farther than max(nearest so far, radius)
  // (the boxes' gap to the segment's box, then the segment's own max-norm distance).
  double nearest = std::numeric_limits<double>::infinity();
  double reach = std::numeric_limits<double>::infinity();  // max(nearest, radius), widened
  TouchingHulls touching;
  // Two entries per level at most, and the median split keeps the tree about log2(hulls) deep.
  struct Pending {
    int node;
    double gap_squared;
  } stack[128];
  int top = 0;
  stack[top++] = {0, boxGapSquared(lo, hi, nodes[0].lo, nodes[0].hi)};
  while (top > 0) {
    const Pending pending = stack[--top];
    if (pending.gap_squared > reach * reach) continue;
    const BoxNode& node = nodes[std::size_t(pending.node)];
    if (node.left < 0) {
      if (!ray.near(node.lo, node.hi, reach)) continue;
      // Exact only where it matters: a hull within radius is touching whatever its distance, and
      // one proven beyond the reach is neither touching nor the nearest.
      const detail::DistanceCertificate c =
          detail::certifiedDistance(a, segment.b, polytopes[std::size_t(node.hull)], radius, reach);
      if (c.upper <= radius) touching.push(node.hull);
      if (c.lower <= reach && c.upper < nearest) {
        nearest = c.upper;
        reach = widen(std::max(nearest, radius));
      }
      continue;
    }
    const BoxNode& l = nodes[std::size_t(node.left)];
    const BoxNode& r = nodes[std::size_t(node.right)];
    const double gap_l = boxGapSquared(lo, hi, l.lo, l.hi), gap_r = boxGapSquared(lo, hi, r.lo, r.hi);
    // The nearer child on top of the stack, visited first.
    assert(top + 2 <= 128);
    if (gap_l <= gap_r) {
      stack[top++] = {node.right, gap_r};
      stack[top++] = {node.left, gap_l};
    } else {
      stack[top++] = {node.left, gap_l};
      stack[top++] = {node.right, gap_r};
    }
  }

  if (touching.size() == 0) {
    result.clearance = nearest - radius;
    return result;
  }
  result.collides = true;
  result.clearance = 0.0;
  const double tolerance = contactTolerance(segment);
  // Hulls in the order the sweep can first reach them; one that cannot be reached before the
  // first contact found so far is not computed.
  for (auto& [bound, hull] : touching) {
    bound = detail::contactLowerBound(a, segment.b, polytopes[std::size_t(hull)], radius);
    if (bound > 1.0) bound = 0.0;  // rounding only: the hull is within radius of the segment
  }
  std::sort(touching.begin(), touching.end());
  double first = std::numeric_limits<double>::infinity();
  int first_hull = -1;
  for (const auto& [bound, hull] : touching) {
    if (bound > first) break;
    const double t =
        detail::firstContactTouching(a, segment.b, polytopes[std::size_t(hull)], radius, tolerance, bound);
    if (t < first || (t == first && hull < first_hull)) {
      first = t;
      first_hull = hull;
    }
  }
  result.t = first;
  result.obstacle = impl_->ids[std::size_t(first_hull)];
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
