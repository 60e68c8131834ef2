// A capsule against the solid under a height field: the union of the convex prisms under its
// triangles, each checked with the certified convex distance (height_field_sweep.hpp).
#include "height_field_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "convex_distance_detail.hpp"

namespace hullmap::collision::detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The field's node lattice grown by one ring of nodes `reach` beyond its span, each at its
/// nearest edge node's height: cells of the grown lattice are the field's cells and the strips
/// and corners around them, where the field is level with its edge.
class GrownLattice {
 public:
  explicit GrownLattice(const HeightField& f) : f_(f) {
    const double reach = f.step * double(f.nx + f.ny);
    xs_.push_back(f.node(0, 0).x() - reach);
    for (std::size_t i = 0; i < f.nx; ++i) xs_.push_back(f.node(i, 0).x());
    xs_.push_back(f.node(f.nx - 1, 0).x() + reach);
    ys_.push_back(f.node(0, 0).y() - reach);
    for (std::size_t j = 0; j < f.ny; ++j) ys_.push_back(f.node(0, j).y());
    ys_.push_back(f.node(0, f.ny - 1).y() + reach);
    bottom_ = f.lowest() - reach;
  }
  std::size_t cellsX() const { return xs_.size() - 1; }
  std::size_t cellsY() const { return ys_.size() - 1; }
  double x(std::size_t k) const { return xs_[k]; }
  double y(std::size_t l) const { return ys_[l]; }
  double bottom() const { return bottom_; }
  /// The grown node (k, l), k in [0, nx + 1], l in [0, ny + 1].
  Eigen::Vector3d node(std::size_t k, std::size_t l) const {
    const std::size_t i = std::clamp<std::size_t>(k, 1, f_.nx) - 1, j = std::clamp<std::size_t>(l, 1, f_.ny) - 1;
    return {xs_[k], ys_[l], f_.at(i, j)};
  }
  /// The cells whose column range [first, last] meets [lo, hi] (clamped to the lattice).
  std::pair<std::size_t, std::size_t> columns(double lo, double hi) const { return range(xs_, lo, hi); }
  std::pair<std::size_t, std::size_t> rows(double lo, double hi) const { return range(ys_, lo, hi); }

 private:
  static std::pair<std::size_t, std::size_t> range(const std::vector<double>& v, double lo, double hi) {
    const auto cell = [&](double c) {
      const auto it = std::upper_bound(v.begin(), v.end(), c);
      const std::ptrdiff_t k = (it - v.begin()) - 1;
      return std::size_t(std::clamp<std::ptrdiff_t>(k, 0, std::ptrdiff_t(v.size()) - 2));
    };
    return {cell(lo), cell(hi)};
  }

  const HeightField& f_;
  std::vector<double> xs_, ys_;
  double bottom_ = 0.0;
};

/// Distance between the 2D segment [a, b] and the rectangle [lo, hi] (0 when they meet).
double segmentRectangleDistance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& lo,
                                const Eigen::Vector2d& hi) {
  // Clip the segment to the rectangle (Liang-Barsky): a piece inside means distance 0.
  double t0 = 0, t1 = 1;
  const Eigen::Vector2d d = b - a;
  bool inside = true;
  for (int k = 0; k < 2 && inside; ++k) {
    if (d[k] == 0) {
      inside = a[k] >= lo[k] && a[k] <= hi[k];
      continue;
    }
    double ta = (lo[k] - a[k]) / d[k], tb = (hi[k] - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    inside = t0 <= t1;
  }
  if (inside) return 0.0;
  // Apart: the least of the ends' distances to the rectangle and the corners' to the segment.
  const auto pointBox = [&](const Eigen::Vector2d& p) { return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).norm(); };
  const auto pointSegment = [&](const Eigen::Vector2d& p) {
    const double len2 = d.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    return (a + t * d - p).norm();
  };
  double best = std::min(pointBox(a), pointBox(b));
  for (const Eigen::Vector2d& c : {lo, hi, Eigen::Vector2d(lo.x(), hi.y()), Eigen::Vector2d(hi.x(), lo.y())})
    best = std::min(best, pointSegment(c));
  return best;
}

/// A bound grown by a hair, so that rounding never drops a prism at the bound.
double widen(double bound) { return bound * (1 + 1e-12) + 1e-12; }

}  // namespace

ConvexPolytope groundPrism(const std::array<Eigen::Vector3d, 3>& top, double bottom) {
  ConvexPolytope p;
  for (const auto& v : top) p.vertices.push_back(v);
  for (const auto& v : top) p.vertices.emplace_back(v.x(), v.y(), bottom);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& v : p.vertices) centre += v / 6.0;
  const auto face = [&](int a, int b, int c) {
    Eigen::Vector3d n = (p.vertices[b] - p.vertices[a]).cross(p.vertices[c] - p.vertices[a]);
    if (n.dot(centre - p.vertices[a]) > 0) {
      std::swap(b, c);
      n = -n;
    }
    n.normalize();
    p.triangles.push_back({a, b, c});
    p.normals.push_back(n);
    p.offsets.push_back(n.dot(p.vertices[a]));
  };
  face(0, 1, 2);
  face(3, 4, 5);
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    face(i, j, j + 3);
    face(i, j + 3, i + 3);
  }
  p.aabb_min = p.aabb_max = p.vertices[0];
  p.scale = 0.0;
  for (const auto& v : p.vertices) {
    p.aabb_min = p.aabb_min.cwiseMin(v);
    p.aabb_max = p.aabb_max.cwiseMax(v);
    p.scale = std::max(p.scale, v.cwiseAbs().maxCoeff());
  }
  return p;
}

SegmentCheck sweepHeightField(const Segment& segment, double radius, const Surface& surface, double t_tolerance) {
  const HeightField& f = *surface.field;
  const GrownLattice lattice(f);
  const Eigen::Vector3d &a = segment.a, &b = segment.b;
  SegmentCheck result;
  // The surface point under an end is in the solid: the end's height over it bounds its distance.
  double nearest = kInf;
  const auto within = [&](const Eigen::Vector3d& p) {
    return p.x() >= lattice.x(0) && p.x() <= lattice.x(lattice.cellsX()) && p.y() >= lattice.y(0) &&
           p.y() <= lattice.y(lattice.cellsY()) && p.z() >= lattice.bottom();
  };
  for (const Eigen::Vector3d* end : {&a, &b})
    if (within(*end)) nearest = std::min(nearest, std::max(0.0, surface.distance(*end)));
  if (within(a) && surface.distance(a) <= radius) {
    result.collides = true;
    result.surface = surface.name;
    result.t = 0.0;
    return result;
  }
  double reach = widen(std::max(nearest, radius));
  // The cells that may lie within reach, nearest first by a lower bound of their prisms' distance.
  struct Cell {
    double bound;
    std::size_t k, l;
    bool operator<(const Cell& o) const { return bound < o.bound; }
  };
  std::vector<Cell> cells;
  const double low = std::min(a.z(), b.z());
  if (std::isfinite(reach)) {
    const auto [k0, k1] = lattice.columns(std::min(a.x(), b.x()) - reach, std::max(a.x(), b.x()) + reach);
    const auto [l0, l1] = lattice.rows(std::min(a.y(), b.y()) - reach, std::max(a.y(), b.y()) + reach);
    for (std::size_t l = l0; l <= l1; ++l)
      for (std::size_t k = k0; k <= k1; ++k) {
        const double top = std::max({lattice.node(k, l).z(), lattice.node(k + 1, l).z(), lattice.node(k, l + 1).z(),
                                     lattice.node(k + 1, l + 1).z()});
        const double flat = segmentRectangleDistance(a.head<2>(), b.head<2>(), {lattice.x(k), lattice.y(l)},
                                                     {lattice.x(k + 1), lattice.y(l + 1)});
        const double bound = std::max(flat, low - top);
        if (bound <= reach) cells.push_back({bound, k, l});
      }
  } else {
    // Both ends beyond the solid's region: every cell (a segment crossing it may still meet it).
    for (std::size_t l = 0; l < lattice.cellsY(); ++l)
      for (std::size_t k = 0; k < lattice.cellsX(); ++k) cells.push_back({0.0, k, l});
  }
  std::sort(cells.begin(), cells.end());
  std::vector<ConvexPolytope> touching;
  for (const Cell& c : cells) {
    if (c.bound > reach) break;
    const Eigen::Vector3d n00 = lattice.node(c.k, c.l), n10 = lattice.node(c.k + 1, c.l);
    const Eigen::Vector3d n01 = lattice.node(c.k, c.l + 1), n11 = lattice.node(c.k + 1, c.l + 1);
    for (const auto& top :
         {std::array<Eigen::Vector3d, 3>{n00, n10, n11}, std::array<Eigen::Vector3d, 3>{n00, n11, n01}}) {
      ConvexPolytope prism = groundPrism(top, lattice.bottom());
      const DistanceCertificate d = certifiedDistance(a, b, prism, radius, reach);
      if (d.lower > reach) continue;
      if (d.upper <= radius) {
        touching.push_back(std::move(prism));
      } else if (d.upper < nearest) {
        nearest = d.upper;
        reach = widen(std::max(nearest, radius));
      }
    }
  }
  if (touching.empty()) {
    result.clearance = nearest - radius;
    return result;
  }
  result.collides = true;
  result.surface = surface.name;
  double first = kInf;
  for (const ConvexPolytope& prism : touching) {
    double bound = contactLowerBound(a, b, prism, radius);
    if (bound > 1.0) bound = 0.0;  // rounding only: the prism is within radius of the segment
    if (bound > first) continue;
    first = std::min(first, firstContactTouching(a, b, prism, radius, t_tolerance, bound));
  }
  result.t = first;
  return result;
}

}  // namespace hullmap::collision::detail
