// The exact lattice hull of the convex split (lattice_hull.hpp says why it is not CGAL's).
#include "lattice_hull.hpp"

#include "hullmap/core/error.hpp"

#include <algorithm>
#include <cstdlib>
#include <numeric>
#include <vector>

namespace hullmap::hulls::detail {
namespace {

/// Hull of integer points (at least four of them not coplanar) as triangles (indices into `points`)
/// oriented outwards, exact: incremental construction whose orientation tests are exact integer
/// determinants (128-bit), so lattice degeneracies (many coplanar points) cost nothing extra. A
/// point on a face's plane does not see that face, so coplanar triangles may remain, and no
/// triangle is degenerate. O(n * faces); the inputs here are the few candidate corners of a part.
/// `Wide` holds the orientation determinants: 128 bits in general, 64 when the points span less
/// than 2^18 cells on every axis (|n . (p - a)| < 6 * 2^54).
template <class Wide>
std::vector<std::array<std::uint32_t, 3>> integerHull(const std::vector<LatticePoint>& points) {
  struct Face {
    std::array<std::uint32_t, 3> v;
    LatticePoint n;  // outward normal, (b - a) x (c - a)
  };
  const auto side = [&](const Face& f, const LatticePoint& p) {  // > 0: p strictly outside the face's plane
    const LatticePoint& a = points[f.v[0]];
    return Wide(f.n[0]) * (p[0] - a[0]) + Wide(f.n[1]) * (p[1] - a[1]) + Wide(f.n[2]) * (p[2] - a[2]);
  };
  std::vector<Face> faces;
  const auto makeFace = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    return Face{{a, b, c}, cross(sub(points[b], points[a]), sub(points[c], points[a]))};
  };
  // A first tetrahedron.
  const std::size_t n = points.size();
  std::size_t i1 = 1, i2 = 0, i3 = 0;
  while (i1 < n && points[i1] == points[0]) ++i1;
  for (i2 = i1 + 1; i2 < n; ++i2)
    if (cross(sub(points[i1], points[0]), sub(points[i2], points[0])) != LatticePoint{0, 0, 0}) break;
  for (i3 = i2 + 1; i3 < n; ++i3) {
    const Face f = makeFace(0, std::uint32_t(i1), std::uint32_t(i2));
    if (side(f, points[i3]) != 0) break;
  }
  if (i3 >= n) throw Error("convex parts: internal error: the corners of a part are coplanar");
  const std::array<std::uint32_t, 4> t{0, std::uint32_t(i1), std::uint32_t(i2), std::uint32_t(i3)};
  for (const auto& [a, b, c, opposite] : {std::array<int, 4>{0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 3, 1}, {1, 2, 3, 0}}) {
    Face f = makeFace(t[std::size_t(a)], t[std::size_t(b)], t[std::size_t(c)]);
    if (side(f, points[t[std::size_t(opposite)]]) > 0)
      f = makeFace(t[std::size_t(a)], t[std::size_t(c)], t[std::size_t(b)]);
    faces.push_back(f);
  }
  // Each point sees the faces it is strictly outside of; the edges of those faces whose reverse
  // edge is on no seen face form the horizon, which the point is joined to.
  std::vector<Face> kept;
  std::vector<char> sees;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> seen_edges, sorted_edges, horizon;
  for (std::size_t i = 1; i < n; ++i) {
    if (i == i1 || i == i2 || i == i3) continue;
    seen_edges.clear();
    sees.resize(faces.size());
    for (std::size_t f = 0; f < faces.size(); ++f) {
      sees[f] = side(faces[f], points[i]) > 0;
      if (sees[f])
        for (int e = 0; e < 3; ++e)
          seen_edges.emplace_back(faces[f].v[std::size_t(e)], faces[f].v[std::size_t((e + 1) % 3)]);
    }
    if (seen_edges.empty()) continue;
    horizon.clear();
    if (seen_edges.size() <= 12) {
      for (const auto& [u, v] : seen_edges)
        if (std::find(seen_edges.begin(), seen_edges.end(), std::make_pair(v, u)) == seen_edges.end())
          horizon.emplace_back(u, v);
    } else {
      sorted_edges = seen_edges;
      std::sort(sorted_edges.begin(), sorted_edges.end());
      for (const auto& [u, v] : seen_edges)
        if (!std::binary_search(sorted_edges.begin(), sorted_edges.end(), std::make_pair(v, u)))
          horizon.emplace_back(u, v);
    }
    kept.clear();
    for (std::size_t f = 0; f < faces.size(); ++f)
      if (!sees[f]) kept.push_back(faces[f]);
    for (const auto& [u, v] : horizon) kept.push_back(makeFace(u, v, std::uint32_t(i)));
    faces.swap(kept);
  }
  std::vector<std::array<std::uint32_t, 3>> out;
  for (const auto& f : faces) out.push_back(f.v);
  return out;
}

}  // namespace

/// Hull of the cells' corners, exact on the lattice: its facet planes and volume do not depend on
/// how it is triangulated, so everything decided from them is deterministic.
FacetHull facetHull(const std::vector<LatticePoint>& cells) {
  const std::vector<LatticePoint> corners = detail::candidateCorners(cells);
  FacetHull hull;
  const LatticePoint& ref = corners[0];
  LatticePoint lo = corners[0], hi = corners[0];
  for (const auto& c : corners)
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], c[a]);
      hi[a] = std::max(hi[a], c[a]);
    }
  const bool narrow = hi[0] - lo[0] < (1 << 18) && hi[1] - lo[1] < (1 << 18) && hi[2] - lo[2] < (1 << 18);
  for (const auto& t : narrow ? integerHull<std::int64_t>(corners) : integerHull<__int128>(corners)) {
    const LatticePoint& p = corners[t[0]];
    const LatticePoint& q = corners[t[1]];
    const LatticePoint& r = corners[t[2]];
    hull.volume6 += dot(sub(p, ref), cross(sub(q, ref), sub(r, ref)));
    LatticePoint n = cross(sub(q, p), sub(r, p));
    const std::int64_t g = std::gcd(std::gcd(std::abs(n[0]), std::abs(n[1])), std::abs(n[2]));
    for (auto& x : n) x /= g;
    hull.planes.push_back({n, dot(n, p)});
  }
  std::sort(hull.planes.begin(), hull.planes.end());
  hull.planes.erase(std::unique(hull.planes.begin(), hull.planes.end(),
                                [](const Plane& a, const Plane& b) { return !(a < b) && !(b < a); }),
                    hull.planes.end());
  return hull;
}

}  // namespace hullmap::hulls::detail
