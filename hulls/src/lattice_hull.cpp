// The exact lattice hull of the convex split (lattice_hull.hpp says why it is not CGAL's) and the
// candidate corners of a cluster's hull, which both hulls start from.
#include "hullmap/hulls/detail/lattice_hull.hpp"

#include "hullmap/core/error.hpp"

#include <algorithm>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <numeric>
#include <vector>

namespace hullmap::hulls::detail {
namespace {

using Corner = LatticePoint;

/// Coordinates relative to a box's low corner are packed 21 bits an axis.
constexpr int kBits = 21;

/// A vector taken from this thread's spare one for a call and given back, capacity kept, at its end: no
/// allocation once warm, and a local the compiler need not reload after every store.
template <class T>
class Borrowed {
 public:
  explicit Borrowed(std::vector<T>& spare) : spare_(spare) {
    v.swap(spare_);
    v.clear();
  }
  ~Borrowed() { v.swap(spare_); }
  Borrowed(const Borrowed&) = delete;
  Borrowed& operator=(const Borrowed&) = delete;
  std::vector<T> v;

 private:
  std::vector<T>& spare_;
};

using Point2 = std::array<std::int64_t, 2>;  // in a plane of the lattice: (y, x), or (u, v)

/// The vertices of the 2D hull of `points` (distinct, sorted), in the same order, into `vertices`
/// (Andrew's monotone chain, exact; collinear points dropped).
void hullVertices(const std::vector<Point2>& points, std::vector<Point2>& vertices) {
  vertices.clear();
  if (points.size() <= 2) {
    vertices = points;
    return;
  }
  const auto turn = [](const Point2& p, const Point2& q, const Point2& r) {
    return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
  };
  for (const auto& q : points) {
    while (vertices.size() >= 2 && turn(vertices[vertices.size() - 2], vertices.back(), q) <= 0) vertices.pop_back();
    vertices.push_back(q);
  }
  const std::size_t lower = vertices.size();
  for (std::size_t k = points.size() - 1; k-- > 0;) {
    while (vertices.size() > lower && turn(vertices[vertices.size() - 2], vertices.back(), points[k]) <= 0)
      vertices.pop_back();
    vertices.push_back(points[k]);
  }
  vertices.pop_back();  // the first point again
  // The lower chain runs up in order, the upper one back down: merged, the upper one read backwards,
  // into a spare vector (inplace_merge would allocate a buffer on every call).
  thread_local std::vector<Point2> spare_merged;
  Borrowed<Point2> merged(spare_merged);
  std::merge(vertices.begin(), vertices.begin() + std::ptrdiff_t(lower), vertices.rbegin(),
             std::make_reverse_iterator(vertices.begin() + std::ptrdiff_t(lower)), std::back_inserter(merged.v));
  std::copy(merged.v.begin(), merged.v.end(), vertices.begin());
}

/// Keeps, in each plane of constant coordinate `axis`, only the vertices of the 2D convex hull of
/// the points lying in that plane (Andrew's monotone chain, exact in integers; collinear points
/// dropped). A point that is no vertex of its plane's hull is a convex combination of other points
/// of the set, so it is no vertex of the 3D hull either: the 3D hull is unchanged.
void keepPlaneHullVertices(std::vector<Corner>& points, int axis) {
  const std::size_t a = std::size_t(axis), u = std::size_t((axis + 1) % 3), v = std::size_t((axis + 2) % 3);
  if (points.empty()) return;
  Corner lo = points[0], hi = points[0];
  for (const auto& p : points)
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  if (hi[0] - lo[0] < (1 << kBits) && hi[1] - lo[1] < (1 << kBits) && hi[2] - lo[2] < (1 << kBits)) {
    // Sorted as packed (a, u, v) keys: the same order, faster.
    constexpr std::uint64_t kMask = (std::uint64_t(1) << kBits) - 1;
    thread_local std::vector<std::uint64_t> spare_keys;
    Borrowed<std::uint64_t> borrowed_keys(spare_keys);
    std::vector<std::uint64_t>& keys = borrowed_keys.v;
    for (const auto& p : points)
      keys.push_back(std::uint64_t(p[a] - lo[a]) << (2 * kBits) | std::uint64_t(p[u] - lo[u]) << kBits |
                     std::uint64_t(p[v] - lo[v]));
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    points.resize(keys.size());
    for (std::size_t k = 0; k < keys.size(); ++k) {
      points[k][a] = std::int64_t(keys[k] >> (2 * kBits)) + lo[a];
      points[k][u] = std::int64_t((keys[k] >> kBits) & kMask) + lo[u];
      points[k][v] = std::int64_t(keys[k] & kMask) + lo[v];
    }
  } else {
    std::sort(points.begin(), points.end(), [&](const Corner& p, const Corner& q) {
      return std::tie(p[a], p[u], p[v]) < std::tie(q[a], q[u], q[v]);
    });
    points.erase(std::unique(points.begin(), points.end()), points.end());
  }
  thread_local std::vector<Corner> spare_out;
  thread_local std::vector<Point2> spare_plane, spare_vertices;
  Borrowed<Corner> borrowed_out(spare_out);
  Borrowed<Point2> plane(spare_plane), vertices(spare_vertices);
  std::vector<Corner>& out = borrowed_out.v;
  for (std::size_t begin = 0; begin < points.size();) {
    plane.v.clear();  // the plane's points as (u, v), sorted
    std::size_t end = begin;
    for (; end < points.size() && points[end][a] == points[begin][a]; ++end)
      plane.v.push_back({points[end][u], points[end][v]});
    hullVertices(plane.v, vertices.v);
    for (const auto& q : vertices.v) {
      Corner c;
      c[a] = points[begin][a];
      c[u] = q[0];
      c[v] = q[1];
      out.push_back(c);
    }
    begin = end;
  }
  points.swap(out);
}

/// A row of cells (z = k, y = j): as far as the hull of its cells' corners goes, the squares from
/// x0 to x1 (its least cell x and its greatest cell x + 1).
struct Row {
  std::int64_t k, j, x0, x1;
};

/// The rows of `cells` (within the box lo..hi, narrower than 2^kBits on every axis) in (k, j) order.
/// A grid of the box's (k, j) rows when it has at most 8 entries a cell (every cell visited once, no
/// sort); otherwise the cells sorted as packed (k, j, i) keys.
void rowsOf(const std::vector<Corner>& cells, const Corner& lo, const Corner& hi, std::vector<Row>& rows) {
  rows.clear();
  const std::int64_t ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
  if (ny * nz <= 8 * std::int64_t(cells.size())) {
    thread_local std::vector<std::array<std::int32_t, 2>> spare_grid;
    Borrowed<std::array<std::int32_t, 2>> borrowed_grid(spare_grid);
    std::vector<std::array<std::int32_t, 2>>& grid = borrowed_grid.v;  // per (k, j): least x, greatest x + 1
    grid.assign(std::size_t(ny * nz), {std::numeric_limits<std::int32_t>::max(), 0});
    for (const auto& c : cells) {
      auto& e = grid[std::size_t((c[2] - lo[2]) * ny + (c[1] - lo[1]))];
      const auto x = std::int32_t(c[0] - lo[0]);
      e[0] = std::min(e[0], x);
      e[1] = std::max(e[1], x + 1);
    }
    for (std::int64_t k = 0; k < nz; ++k)
      for (std::int64_t j = 0; j < ny; ++j) {
        const auto& e = grid[std::size_t(k * ny + j)];
        if (e[0] < e[1]) rows.push_back({k + lo[2], j + lo[1], e[0] + lo[0], e[1] + lo[0]});
      }
    return;
  }
  thread_local std::vector<std::uint64_t> spare_keys;
  Borrowed<std::uint64_t> borrowed_keys(spare_keys);
  std::vector<std::uint64_t>& keys = borrowed_keys.v;
  for (const auto& c : cells)
    keys.push_back(std::uint64_t(c[2] - lo[2]) << (2 * kBits) | std::uint64_t(c[1] - lo[1]) << kBits |
                   std::uint64_t(c[0] - lo[0]));
  std::sort(keys.begin(), keys.end());
  constexpr std::uint64_t kMask = (std::uint64_t(1) << kBits) - 1;
  for (std::size_t begin = 0; begin < keys.size();) {
    const std::uint64_t row = keys[begin] >> kBits;
    std::size_t end = begin + 1;
    while (end < keys.size() && keys[end] >> kBits == row) ++end;
    rows.push_back({std::int64_t(row >> kBits) + lo[2], std::int64_t(row & kMask) + lo[1],
                    std::int64_t(keys[begin] & kMask) + lo[0], std::int64_t(keys[end - 1] & kMask) + 1 + lo[0]});
    begin = end;
  }
}

/// gcd of two non-negative integers (binary: shifts instead of divisions).
std::uint64_t gcd(std::uint64_t a, std::uint64_t b) {
  if (a == 0) return b;
  if (b == 0) return a;
  const int shift = __builtin_ctzll(a | b);
  a >>= __builtin_ctzll(a);
  do {
    b >>= __builtin_ctzll(b);
    if (a > b) std::swap(a, b);
    b -= a;
  } while (b != 0);
  return a << shift;
}

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
  thread_local std::vector<Face> spare_faces;
  Borrowed<Face> borrowed_faces(spare_faces);
  std::vector<Face>& faces = borrowed_faces.v;
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
  // edge is on no seen face form the horizon, which the point is joined to. The seen edges go into a
  // small open-addressing table (keys u << 32 | v, plus one: 0 is empty); the new faces take the seen
  // faces' places, the rest are appended or the places left over removed (the hull's faces as a set
  // do not depend on their order).
  thread_local std::vector<std::uint32_t> spare_seen;
  thread_local std::vector<std::uint64_t> spare_table;
  thread_local std::vector<std::pair<std::uint32_t, std::uint32_t>> spare_horizon;
  Borrowed<std::uint32_t> borrowed_seen(spare_seen);
  Borrowed<std::uint64_t> borrowed_table(spare_table);
  Borrowed<std::pair<std::uint32_t, std::uint32_t>> borrowed_horizon(spare_horizon);
  std::vector<std::uint32_t>& seen = borrowed_seen.v;
  std::vector<std::uint64_t>& table = borrowed_table.v;
  std::vector<std::pair<std::uint32_t, std::uint32_t>>& horizon = borrowed_horizon.v;
  const auto slot = [&](std::uint64_t key) {  // the key's slot, or the empty one where it would go
    std::size_t at = std::size_t((key * 0x9E3779B97F4A7C15ull) >> 40) & (table.size() - 1);
    while (table[at] != 0 && table[at] != key) at = (at + 1) & (table.size() - 1);
    return at;
  };
  const auto edgeKey = [](std::uint32_t u, std::uint32_t v) { return (std::uint64_t(u) << 32 | v) + 1; };
  for (std::size_t i = 1; i < n; ++i) {
    if (i == i1 || i == i2 || i == i3) continue;
    seen.clear();
    for (std::size_t f = 0; f < faces.size(); ++f)
      if (side(faces[f], points[i]) > 0) seen.push_back(std::uint32_t(f));
    if (seen.empty()) continue;
    std::size_t size = 16;
    while (size < 6 * seen.size()) size *= 2;  // at most half full
    table.assign(size, 0);
    for (const std::uint32_t f : seen)
      for (std::size_t e = 0; e < 3; ++e) {
        const std::uint64_t key = edgeKey(faces[f].v[e], faces[f].v[(e + 1) % 3]);
        table[slot(key)] = key;
      }
    horizon.clear();
    for (const std::uint32_t f : seen)
      for (std::size_t e = 0; e < 3; ++e) {
        const std::uint32_t u = faces[f].v[e], v = faces[f].v[(e + 1) % 3];
        if (table[slot(edgeKey(v, u))] == 0) horizon.emplace_back(u, v);
      }
    for (std::size_t k = 0; k < horizon.size(); ++k) {
      const Face face = makeFace(horizon[k].first, horizon[k].second, std::uint32_t(i));
      if (k < seen.size())
        faces[seen[k]] = face;
      else
        faces.push_back(face);
    }
    for (std::size_t k = seen.size(); k-- > horizon.size();) {  // places left over, the last first
      faces[seen[k]] = faces.back();
      faces.pop_back();
    }
  }
  std::vector<std::array<std::uint32_t, 3>> out;
  for (const auto& f : faces) out.push_back(f.v);
  return out;
}

}  // namespace

/// Corners that can be vertices of the hull of all voxel corners: each plane z = c holds the top face
/// of layer c - 1 and the bottom face of layer c, unions of squares whose 2D hull comes from their
/// rows' first and last cells (rowsOf); the vertices of that 2D hull are kept, then only the vertices
/// of the 2D hull of each plane x = c and y = c (keepPlaneHullVertices). Exact (integer lattice),
/// never drops a hull vertex; O(n) for a cluster whose box has at most 8 (z, y) rows a cell, else
/// O(n log n).
std::vector<LatticePoint> candidateCorners(const std::vector<LatticePoint>& cells) {
  if (cells.empty()) return {};
  Corner lo = cells[0], hi = cells[0];
  for (const auto& c : cells)
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], c[a]);
      hi[a] = std::max(hi[a], c[a]);
    }
  std::vector<Corner> out;
  if (hi[0] - lo[0] >= (1 << kBits) || hi[1] - lo[1] >= (1 << kBits) || hi[2] - lo[2] >= (1 << kBits)) {
    // Too wide to pack: every cell's corners.
    for (const auto& c : cells)
      for (int m = 0; m < 8; ++m) out.push_back({c[0] + (m & 1), c[1] + ((m >> 1) & 1), c[2] + ((m >> 2) & 1)});
    keepPlaneHullVertices(out, 2);
  } else {
    // Per layer z = k of cells, the vertices of the 2D hull of its squares (from the lines y = j and
    // j + 1 of its rows); plane z = c holds the top of layer c - 1 and the bottom of layer c.
    thread_local std::vector<Row> spare_rows;
    thread_local std::vector<Point2> spare_points, spare_below, spare_above, spare_plane;
    Borrowed<Row> rows(spare_rows);
    Borrowed<Point2> points(spare_points), below(spare_below), above(spare_above), plane(spare_plane);
    rowsOf(cells, lo, hi, rows.v);
    const auto emit = [&](const std::vector<Point2>& vertices, std::int64_t z) {
      for (const auto& q : vertices) out.push_back({q[1], q[0], z});
    };
    std::int64_t below_k = 0;  // the layer `below` holds, when not empty
    for (std::size_t r = 0; r < rows.v.size();) {
      const std::int64_t k = rows.v[r].k;
      points.v.clear();
      for (; r < rows.v.size() && rows.v[r].k == k; ++r) {
        const Row& row = rows.v[r];
        for (const std::int64_t y : {row.j, row.j + 1}) {
          if (!points.v.empty() && points.v.back()[0] == y) {
            points.v[points.v.size() - 2][1] = std::min(points.v[points.v.size() - 2][1], row.x0);
            points.v.back()[1] = std::max(points.v.back()[1], row.x1);
          } else {
            points.v.push_back({y, row.x0});
            points.v.push_back({y, row.x1});
          }
        }
      }
      hullVertices(points.v, above.v);
      if (!below.v.empty() && below_k + 1 == k) {
        points.v.clear();
        std::merge(below.v.begin(), below.v.end(), above.v.begin(), above.v.end(), std::back_inserter(points.v));
        points.v.erase(std::unique(points.v.begin(), points.v.end()), points.v.end());
        hullVertices(points.v, plane.v);
        emit(plane.v, k);
      } else {
        emit(below.v, below_k + 1);  // the top of the layer below alone (nothing when there is none)
        emit(above.v, k);
      }
      below.v.swap(above.v);
      below_k = k;
    }
    emit(below.v, below_k + 1);
  }
  for (const int axis : {0, 1}) keepPlaneHullVertices(out, axis);
  return out;
}

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
  // Facet normals reach 8 B^2 and offsets and volume terms 48 B^3 for corners within B of the origin:
  // 64 bits hold them for B = 2^18. A cluster's lattice starts at its own corner, and an octree has
  // at most 2^16 voxels an axis, so only cells given to the library directly can reach this.
  constexpr std::int64_t kReach = std::int64_t(1) << 18;
  for (std::size_t a = 0; a < 3; ++a)
    if (lo[a] <= -kReach || hi[a] >= kReach)
      throw Error(
          "convex parts: a part reaches 2^18 voxels or more from its lattice's origin: too wide for the "
          "exact lattice hull");
  const bool narrow = hi[0] - lo[0] < (1 << 18) && hi[1] - lo[1] < (1 << 18) && hi[2] - lo[2] < (1 << 18);
  for (const auto& t : narrow ? integerHull<std::int64_t>(corners) : integerHull<__int128>(corners)) {
    const LatticePoint& p = corners[t[0]];
    const LatticePoint& q = corners[t[1]];
    const LatticePoint& r = corners[t[2]];
    hull.volume6 += dot(sub(p, ref), cross(sub(q, ref), sub(r, ref)));
    LatticePoint n = cross(sub(q, p), sub(r, p));
    const auto g = std::int64_t(
        gcd(gcd(std::uint64_t(std::abs(n[0])), std::uint64_t(std::abs(n[1]))), std::uint64_t(std::abs(n[2]))));
    if (g != 1)
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
