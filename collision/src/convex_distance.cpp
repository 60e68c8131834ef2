#include "hullmap/collision/convex_distance.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "convex_distance_detail.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::collision {
namespace {

using V3 = Eigen::Vector3d;

/// Up to four points of the Minkowski difference (segment - polytope).
struct Simplex {
  V3 p[4] = {V3::Zero(), V3::Zero(), V3::Zero(), V3::Zero()};
  int n = 0;
};

V3 closestOnSegment(Simplex& s) {
  const V3 a = s.p[0];
  const V3 ab = s.p[1] - a;
  const double t = -a.dot(ab);
  const double len2 = ab.squaredNorm();
  if (t <= 0 || len2 <= 0) {
    s.n = 1;
    return a;
  }
  if (t >= len2) {
    s.p[0] = s.p[1];
    s.n = 1;
    return s.p[0];
  }
  return a + ab * (t / len2);
}

/// Closest point of triangle s.p[0..2] to the origin (Ericson 5.1.5); keeps only the feature it lies on.
V3 closestOnTriangle(Simplex& s) {
  const V3 a = s.p[0], b = s.p[1], c = s.p[2];
  const V3 ab = b - a, ac = c - a;
  const double d1 = -ab.dot(a), d2 = -ac.dot(a);
  if (d1 <= 0 && d2 <= 0) {
    s.n = 1;
    return a;
  }
  const double d3 = -ab.dot(b), d4 = -ac.dot(b);
  if (d3 >= 0 && d4 <= d3) {
    s.p[0] = b;
    s.n = 1;
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    s.n = 2;
    return a + ab * (d1 / (d1 - d3));
  }
  const double d5 = -ab.dot(c), d6 = -ac.dot(c);
  if (d6 >= 0 && d5 <= d6) {
    s.p[0] = c;
    s.n = 1;
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    s.p[1] = c;
    s.n = 2;
    return a + ac * (d2 / (d2 - d6));
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    s.p[0] = b;
    s.p[1] = c;
    s.n = 2;
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) {
    // Degenerate (collinear) triangle: the closest of its three edges.
    V3 best = V3::Constant(std::numeric_limits<double>::infinity());
    Simplex keep;
    const int edges[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    for (const auto& e : edges) {
      Simplex t;
      t.p[0] = s.p[e[0]];
      t.p[1] = s.p[e[1]];
      t.n = 2;
      const V3 q = closestOnSegment(t);
      if (q.squaredNorm() < best.squaredNorm()) {
        best = q;
        keep = t;
      }
    }
    s = keep;
    return best;
  }
  s.n = 3;
  return a + ab * (vb / sum) + ac * (vc / sum);
}

/// Closest point of tetrahedron s.p[0..3] to the origin; zero (and n = 4) when it contains the origin.
V3 closestOnTetrahedron(Simplex& s) {
  const V3 a = s.p[0], b = s.p[1], c = s.p[2], d = s.p[3];
  const double vol = (b - a).dot((c - a).cross(d - a));
  const double size = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (d - a).squaredNorm()});
  bool skip[4] = {false, false, false, false};
  if (std::abs(vol) > 1e-12 * size * std::sqrt(size)) {
    // Barycentric coordinates of the origin; lambda_i < 0: the origin is beyond the face opposite i.
    const double lb = (-a).dot((c - a).cross(d - a)) / vol;
    const double lc = (b - a).dot((-a).cross(d - a)) / vol;
    const double ld = (b - a).dot((c - a).cross(-a)) / vol;
    const double la = 1.0 - lb - lc - ld;
    if (la >= 0 && lb >= 0 && lc >= 0 && ld >= 0) {
      s.n = 4;
      return V3::Zero();
    }
    skip[0] = la >= 0;
    skip[1] = lb >= 0;
    skip[2] = lc >= 0;
    skip[3] = ld >= 0;
  }
  V3 best = V3::Constant(std::numeric_limits<double>::infinity());
  Simplex keep;
  for (int opposite = 0; opposite < 4; ++opposite) {
    if (skip[opposite]) continue;
    Simplex f;
    for (int k = 0; k < 4; ++k)
      if (k != opposite) f.p[f.n++] = s.p[k];
    const V3 q = closestOnTriangle(f);
    if (q.squaredNorm() < best.squaredNorm()) {
      best = q;
      keep = f;
    }
  }
  s = keep;
  return best;
}

V3 closestOnSimplex(Simplex& s) {
  switch (s.n) {
    case 1:
      return s.p[0];
    case 2:
      return closestOnSegment(s);
    case 3:
      return closestOnTriangle(s);
    default:
      return closestOnTetrahedron(s);
  }
}

const V3& supportVertex(const ConvexPolytope& polytope, const V3& direction) {
  std::size_t best = 0;
  double best_value = direction.dot(polytope.vertices[0]);
  for (std::size_t i = 1; i < polytope.vertices.size(); ++i) {
    const double value = direction.dot(polytope.vertices[i]);
    if (value > best_value) {
      best_value = value;
      best = i;
    }
  }
  return polytope.vertices[best];
}

double segmentTriangleDistance(const V3& a, const V3& b, const V3& t0, const V3& t1, const V3& t2) {
  return std::min({pointTriangleDistance(a, t0, t1, t2), pointTriangleDistance(b, t0, t1, t2),
                   segmentSegmentDistance(a, b, t0, t1), segmentSegmentDistance(a, b, t1, t2),
                   segmentSegmentDistance(a, b, t2, t0)});
}

}  // namespace

ConvexPolytope ConvexPolytope::fromHull(const hulls::ConvexHull& hull, const std::string& what) {
  ConvexPolytope p;
  p.vertices = hull.vertices;
  p.triangles = hull.triangles;
  if (p.vertices.size() < 4 || p.triangles.size() < 4)
    throw Error(what + ": hull needs at least 4 vertices and 4 triangles");
  p.aabb_min = p.aabb_max = p.vertices[0];
  for (const auto& v : p.vertices) {
    if (!v.allFinite()) throw Error(what + ": non-finite hull vertex");
    p.aabb_min = p.aabb_min.cwiseMin(v);
    p.aabb_max = p.aabb_max.cwiseMax(v);
  }
  p.scale = std::max({1.0, p.aabb_min.cwiseAbs().maxCoeff(), p.aabb_max.cwiseAbs().maxCoeff()});
  const double extent = (p.aabb_max - p.aabb_min).norm();
  std::map<std::pair<int, int>, int> edge_uses;
  double volume = 0.0;
  for (const auto& t : p.triangles) {
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || t[k] >= int(p.vertices.size())) throw Error(what + ": triangle vertex index out of range");
      ++edge_uses[{t[k], t[(k + 1) % 3]}];
    }
    const V3& a = p.vertices[t[0]];
    const V3 n = (p.vertices[t[1]] - a).cross(p.vertices[t[2]] - a);
    if (n.norm() > 1e-12 * extent * extent) {
      p.normals.push_back(n.normalized());
      p.offsets.push_back(p.normals.back().dot(a));
    } else {
      // A sliver (rounded collinear corners): its plane is meaningless, its neighbours bound the
      // hull within the sliver's width. No half-space, never "facing".
      p.normals.push_back(V3::Zero());
      p.offsets.push_back(std::numeric_limits<double>::infinity());
    }
    volume += a.dot(p.vertices[t[1]].cross(p.vertices[t[2]])) / 6.0;
  }
  // Closed and consistently oriented: every directed edge once, its reverse once.
  for (const auto& [edge, uses] : edge_uses) {
    const auto reverse = edge_uses.find({edge.second, edge.first});
    if (uses != 1 || reverse == edge_uses.end() || reverse->second != 1)
      throw Error(what + ": hull is not a closed, consistently oriented triangle mesh");
  }
  if (!(volume > 0)) throw Error(what + ": hull has no positive volume (triangles not outward?)");
  const double tolerance = 1e-9 * std::max(p.scale, extent);
  for (std::size_t f = 0; f < p.normals.size(); ++f)
    for (const auto& v : p.vertices) {
      if (!std::isfinite(p.offsets[f])) continue;
      if (p.normals[f].dot(v) > p.offsets[f] + tolerance)
        throw Error(what + ": hull is not convex (a vertex is " + std::to_string(p.normals[f].dot(v) - p.offsets[f]) +
                    " outside face " + std::to_string(f) + ")");
    }
  return p;
}

V3 closestPointOnTriangle(const V3& p, const V3& a, const V3& b, const V3& c) {
  const V3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const V3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const V3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

double pointTriangleDistance(const V3& p, const V3& a, const V3& b, const V3& c) {
  return (p - closestPointOnTriangle(p, a, b, c)).norm();
}

double segmentSegmentDistance(const V3& p0, const V3& p1, const V3& q0, const V3& q1) {
  // Ericson 5.1.9 (closest points of two segments), with the degenerate cases.
  const V3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 0 && e <= 0) return r.norm();
  if (a <= 0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + d1 * s) - (q0 + d2 * t)).norm();
}

double segmentPolytopeDistanceBruteForce(const V3& a, const V3& b, const ConvexPolytope& polytope) {
  // Cyrus-Beck: the part of the segment inside every half-space.
  const V3 d = b - a;
  double t0 = 0, t1 = 1;
  bool inside = true;
  for (std::size_t f = 0; f < polytope.normals.size() && inside; ++f) {
    const double num = polytope.offsets[f] - polytope.normals[f].dot(a);
    const double den = polytope.normals[f].dot(d);
    if (den == 0) {
      inside = num >= 0;
    } else if (den > 0) {
      t1 = std::min(t1, num / den);
    } else {
      t0 = std::max(t0, num / den);
    }
    inside = inside && t0 <= t1;
  }
  if (inside) return 0.0;
  // Otherwise the closest point of the polytope is on a face whose plane has the segment in front.
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < polytope.triangles.size(); ++f) {
    const double front = std::max(polytope.normals[f].dot(a), polytope.normals[f].dot(b)) - polytope.offsets[f];
    if (front < -1e-9 * polytope.scale) continue;
    const auto& t = polytope.triangles[f];
    best = std::min(
        best, segmentTriangleDistance(a, b, polytope.vertices[t[0]], polytope.vertices[t[1]], polytope.vertices[t[2]]));
  }
  return best;
}

namespace {

detail::DistanceCertificate bruteForceCertificate(const V3& a, const V3& b, const ConvexPolytope& polytope) {
  detail::DistanceCertificate certificate;
  certificate.upper = segmentPolytopeDistanceBruteForce(a, b, polytope);
  return certificate;  // no plane: lower bound 0
}

}  // namespace

namespace detail {

DistanceCertificate certifiedDistance(const V3& a, const V3& b, const ConvexPolytope& polytope, double settle_at,
                                      double give_up_beyond) {
  const double tol_abs = 1e-9 * std::max(polytope.scale, std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()));
  DistanceCertificate certificate;
  // Start from the pair the boxes suggest: the segment's point nearest the polytope's box centre,
  // and the polytope's vertex farthest towards it.
  const V3 centre = 0.5 * (polytope.aabb_min + polytope.aabb_max);
  const V3 d = b - a;
  const double dd = d.squaredNorm();
  const V3 nearest = dd > 0 ? V3(a + std::clamp((centre - a).dot(d) / dd, 0.0, 1.0) * d) : a;
  Simplex s;
  s.p[0] = nearest - supportVertex(polytope, nearest - centre);
  s.n = 1;
  V3 v = s.p[0];
  for (int iteration = 0; iteration < 64; ++iteration) {
    const double vv = v.squaredNorm();
    const double vn = std::sqrt(vv);
    // The closest point v is realised by a pair of points: vn is an upper bound.
    if (vn <= tol_abs || vn <= settle_at) {
      certificate.upper = vn;
      return certificate;
    }
    // Support of (segment - polytope) in direction -v; v.w / |v| is a lower bound (separating plane).
    const V3 w = (v.dot(a) <= v.dot(b) ? a : b) - supportVertex(polytope, v);
    const double lower = v.dot(w) / vn;
    if (lower > certificate.lower) {
      certificate.lower = lower;
      certificate.normal = v / vn;
    }
    if (vn - certificate.lower <= std::max(tol_abs, 1e-10 * vn) || certificate.lower > give_up_beyond) {
      certificate.upper = vn;
      return certificate;
    }
    for (int k = 0; k < s.n; ++k)
      if (s.p[k] == w) return bruteForceCertificate(a, b, polytope);
    s.p[s.n++] = w;
    v = closestOnSimplex(s);
    if (s.n == 4) {
      certificate.upper = 0.0;
      return certificate;
    }
  }
  return bruteForceCertificate(a, b, polytope);
}

}  // namespace detail

double segmentPolytopeDistance(const V3& a, const V3& b, const ConvexPolytope& polytope) {
  return detail::certifiedDistance(a, b, polytope, -1.0, std::numeric_limits<double>::infinity()).upper;
}

namespace {

/// Smallest t with the sweep touching, by bisection on the prefix distance (non-increasing in t),
/// knowing that the sweep touches by t = 1 and not before `lo`.
double bisectContact(const V3& a, const V3& b, const ConvexPolytope& polytope, double radius, double t_tolerance,
                     double lo) {
  const V3 d = b - a;
  const V3 from = a + lo * d;
  double hi = 1;
  while (hi - lo > t_tolerance) {
    const double mid = 0.5 * (lo + hi);
    if (segmentPolytopeDistance(from, a + mid * d, polytope) <= radius) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  return hi;
}

}  // namespace

double detail::contactLowerBound(const V3& a, const V3& b, const ConvexPolytope& polytope, double radius) {
  // The polytope grown by `radius` (every point within radius of it) lies inside its face planes
  // pushed out by `radius`: the sweep cannot touch before the segment is inside all of them, so
  // before it has crossed every plane it starts outside of. (Slivers: zero normal, infinite offset,
  // never crossed.)
  const V3 d = b - a;
  double t = 0;
  for (std::size_t f = 0; f < polytope.normals.size(); ++f) {
    const double outside = polytope.normals[f].dot(a) - polytope.offsets[f] - radius;
    if (outside <= 0) continue;
    const double approach = -polytope.normals[f].dot(d);
    if (approach <= 0) return 2.0;  // outside this plane and not moving in: never touches
    if (outside > t * approach) t = outside / approach;
  }
  return t;
}

double detail::firstContactTouching(const V3& a, const V3& b, const ConvexPolytope& polytope, double radius,
                                    double t_tolerance, double lower_bound) {
  const V3 d = b - a;
  const double length = d.norm();
  double lo = std::clamp(lower_bound, 0.0, 1.0);
  if (lo == 0 && segmentPolytopeDistance(a, a, polytope) <= radius) return 0.0;
  // Each step evaluates the point q = lo + tolerance / 2: within radius there, q is the answer (the
  // contact lies in [lo, q], so q is at most half the tolerance late). Else the distance
  // certificate at q (a plane separating q from the polytope by `lower`) bounds the distance along
  // the whole line from below, and so where the sweep can first touch: a Newton step on the convex
  // distance, never past the contact.
  for (int iteration = 0; iteration < 32; ++iteration) {
    const double q = std::min(1.0, lo + 0.5 * t_tolerance);
    const DistanceCertificate c =
        certifiedDistance(a + q * d, a + q * d, polytope, radius, std::numeric_limits<double>::infinity());
    if (c.upper <= radius) return q;
    if (!(c.lower > radius)) break;  // undecided within the distance's own tolerance
    const double slope = c.normal.dot(d);
    // Distance along the line >= c.lower + (t - q) * slope: no contact after q when slope >= 0,
    // so the (known) contact is in [lo, q).
    if (slope >= 0) return q;
    const double next = q + (c.lower - radius) / std::min(-slope, length);
    if (!(next <= 1.0)) break;  // only by rounding: the sweep is known to touch by t = 1
    lo = next;
  }
  return bisectContact(a, b, polytope, radius, t_tolerance, lo);
}

std::optional<double> firstContact(const V3& a, const V3& b, const ConvexPolytope& polytope, double radius,
                                   double t_tolerance) {
  if (segmentPolytopeDistance(a, b, polytope) > radius) return std::nullopt;
  const double lower = detail::contactLowerBound(a, b, polytope, radius);
  return detail::firstContactTouching(a, b, polytope, radius, t_tolerance, lower > 1.0 ? 0.0 : lower);
}

}  // namespace hullmap::collision
