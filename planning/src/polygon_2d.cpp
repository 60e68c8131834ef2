#include "polygon_2d.hpp"

#include <algorithm>
#include <cmath>

#include "hullmap/core/convex_hull_2d.hpp"
#include "hullmap/hulls/obstacles.hpp"

namespace hullmap::planning {

double segmentDistance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

double segmentsDistance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                        const Eigen::Vector2d& d) {
  const auto side = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
    return (q - p).x() * (r - p).y() - (q - p).y() * (r - p).x();
  };
  if (side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0) return 0.0;
  return std::min(
      {segmentDistance(a, b, c), segmentDistance(a, b, d), segmentDistance(c, d, a), segmentDistance(c, d, b)});
}

bool insideRings(const std::vector<std::vector<Eigen::Vector2d>>& rings, const Eigen::Vector2d& p) {
  bool inside = false;
  for (const auto& ring : rings)
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
      const Eigen::Vector2d& a = ring[i];
      const Eigen::Vector2d& b = ring[j];
      if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
        inside = !inside;
    }
  return inside;
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
}

bool polygonsMeet(const std::vector<Eigen::Vector2d>& P, const std::vector<Eigen::Vector2d>& Q, double eps) {
  auto inside = [](const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
    for (std::size_t i = 0; i < poly.size(); ++i)
      if (cross(poly[i], poly[(i + 1) % poly.size()], p) < 0) return false;
    return true;
  };
  for (const auto& p : P)
    if (inside(Q, p)) return true;
  for (const auto& q : Q)
    if (inside(P, q)) return true;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const Eigen::Vector2d& a = P[i];
    const Eigen::Vector2d& b = P[(i + 1) % P.size()];
    for (std::size_t j = 0; j < Q.size(); ++j) {
      const Eigen::Vector2d& c = Q[j];
      const Eigen::Vector2d& d = Q[(j + 1) % Q.size()];
      if (segmentDistance(a, b, c) <= eps || segmentDistance(c, d, a) <= eps) return true;
      if (cross(a, b, c) * cross(a, b, d) < 0 && cross(c, d, a) * cross(c, d, b) < 0) return true;
    }
  }
  return false;
}

bool selfIntersecting(const std::vector<std::vector<Eigen::Vector2d>>& rings) {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> segs;
  for (const auto& ring : rings)
    for (std::size_t k = 0; k < ring.size(); ++k) {
      Eigen::Vector2d a = ring[k], b = ring[(k + 1) % ring.size()];
      if (b.x() < a.x()) std::swap(a, b);
      segs.emplace_back(a, b);
    }
  std::sort(segs.begin(), segs.end(), [](const auto& s, const auto& t) { return s.first.x() < t.first.x(); });
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const auto& [a, b] = segs[i];
    for (std::size_t j = i + 1; j < segs.size() && segs[j].first.x() <= b.x(); ++j) {
      const auto& [c, d] = segs[j];
      if (a == c || a == d || b == c || b == d) continue;  // shared ends are fine
      if (std::max(c.y(), d.y()) < std::min(a.y(), b.y()) || std::min(c.y(), d.y()) > std::max(a.y(), b.y())) continue;
      const double c1 = cross(a, b, c), c2 = cross(a, b, d), c3 = cross(c, d, a), c4 = cross(c, d, b);
      if (c1 * c2 <= 0 && c3 * c4 <= 0 && !(c1 == 0 && c2 == 0 && c3 == 0 && c4 == 0)) return true;
      if (c1 == 0 && c2 == 0) {  // collinear: overlapping along x (or y for vertical ones)?
        const int axis = a.x() == b.x() ? 1 : 0;
        const double lo = std::max(std::min(a[axis], b[axis]), std::min(c[axis], d[axis]));
        const double hi = std::min(std::max(a[axis], b[axis]), std::max(c[axis], d[axis]));
        if (lo <= hi) return true;
      }
    }
  }
  return false;
}

std::vector<Eigen::Vector2d> clipToBox(std::vector<Eigen::Vector2d> poly, const Eigen::Vector2d& lo,
                                       const Eigen::Vector2d& hi) {
  for (int side = 0; side < 4 && !poly.empty(); ++side) {
    const int axis = side % 2;
    const bool low = side < 2;
    const double limit = low ? lo[axis] : hi[axis];
    auto in = [&](const Eigen::Vector2d& p) { return low ? p[axis] >= limit : p[axis] <= limit; };
    std::vector<Eigen::Vector2d> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Eigen::Vector2d& a = poly[i];
      const Eigen::Vector2d& b = poly[(i + 1) % poly.size()];
      if (in(a)) out.push_back(a);
      if (in(a) != in(b)) {
        const double t = (limit - a[axis]) / (b[axis] - a[axis]);
        Eigen::Vector2d x = a + t * (b - a);
        x[axis] = limit;
        out.push_back(x);
      }
    }
    poly = std::move(out);
  }
  poly = hullmap::core::convexHull2d(poly);
  return poly.size() >= 3 ? poly : std::vector<Eigen::Vector2d>{};
}

}  // namespace hullmap::planning
