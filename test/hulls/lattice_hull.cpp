// The lattice hull of the convex split against CGAL's convex_hull_3 of every corner of every cell
// (exact predicates on integer coordinates): candidateCorners keeps every vertex of that hull and
// only corners of the cells; facetHull has exactly its facet planes and its volume. On clusters that
// take each path: rows from a grid or from sorted keys, layers with gaps between them, boxes too wide
// to pack and too wide for 64-bit orientation tests.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/hulls/detail/lattice_hull.hpp"

namespace hullmap::hulls::detail {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;

/// CGAL's hull of all the cells' corners: its vertices, its facet planes (primitive outward normal,
/// offset; one per facet, sorted) and six times its volume.
struct Oracle {
  std::set<LatticePoint> vertices;
  std::vector<Plane> planes;
  std::int64_t volume6 = 0;
};

std::set<LatticePoint> allCorners(const std::vector<LatticePoint>& cells) {
  std::set<LatticePoint> corners;
  for (const auto& c : cells)
    for (int m = 0; m < 8; ++m) corners.insert({c[0] + (m & 1), c[1] + ((m >> 1) & 1), c[2] + ((m >> 2) & 1)});
  return corners;
}

Mesh cgalHull(const std::vector<LatticePoint>& cells) {
  std::vector<Kernel::Point_3> points;
  for (const auto& c : allCorners(cells)) points.emplace_back(double(c[0]), double(c[1]), double(c[2]));
  Mesh mesh;
  CGAL::convex_hull_3(points.begin(), points.end(), mesh);
  return mesh;
}

LatticePoint latticeVertex(const Mesh& mesh, Mesh::Vertex_index v) {
  const auto& p = mesh.point(v);
  return {std::int64_t(p.x()), std::int64_t(p.y()), std::int64_t(p.z())};
}

Oracle oracle(const std::vector<LatticePoint>& cells) {
  const Mesh mesh = cgalHull(cells);
  const auto lattice = [&](Mesh::Vertex_index v) { return latticeVertex(mesh, v); };
  Oracle out;
  const LatticePoint ref = lattice(*mesh.vertices().begin());
  for (const auto v : mesh.vertices()) out.vertices.insert(lattice(v));
  for (const auto f : mesh.faces()) {
    std::vector<LatticePoint> t;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) t.push_back(lattice(v));
    EXPECT_EQ(t.size(), 3u);
    out.volume6 += dot(sub(t[0], ref), cross(sub(t[1], ref), sub(t[2], ref)));
    LatticePoint n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
    const std::int64_t g = std::gcd(std::gcd(std::abs(n[0]), std::abs(n[1])), std::abs(n[2]));
    for (auto& x : n) x /= g;
    out.planes.push_back({n, dot(n, t[0])});
  }
  std::sort(out.planes.begin(), out.planes.end());
  out.planes.erase(std::unique(out.planes.begin(), out.planes.end(),
                               [](const Plane& a, const Plane& b) { return !(a < b) && !(b < a); }),
                   out.planes.end());
  return out;
}

void expectMatchesOracle(const std::vector<LatticePoint>& cells, const std::string& what) {
  SCOPED_TRACE(what + ", " + std::to_string(cells.size()) + " cells");
  const Oracle expected = oracle(cells);
  const std::vector<LatticePoint> corners = candidateCorners(cells);
  const std::set<LatticePoint> distinct(corners.begin(), corners.end());
  EXPECT_EQ(distinct.size(), corners.size()) << "a corner given twice";
  const std::set<LatticePoint> all = allCorners(cells);
  for (const auto& c : corners)
    EXPECT_TRUE(all.count(c)) << "not a corner of a cell: " << c[0] << ' ' << c[1] << ' ' << c[2];
  for (const auto& v : expected.vertices)
    EXPECT_TRUE(distinct.count(v)) << "a hull vertex dropped: " << v[0] << ' ' << v[1] << ' ' << v[2];
  const FacetHull hull = facetHull(cells);
  EXPECT_EQ(hull.volume6, expected.volume6);
  ASSERT_EQ(hull.planes.size(), expected.planes.size());
  for (std::size_t k = 0; k < hull.planes.size(); ++k) {
    EXPECT_EQ(hull.planes[k].n, expected.planes[k].n) << "plane " << k;
    EXPECT_EQ(hull.planes[k].d, expected.planes[k].d) << "plane " << k;
  }
}

std::vector<LatticePoint> shifted(std::vector<LatticePoint> cells, const LatticePoint& by) {
  for (auto& c : cells)
    for (std::size_t a = 0; a < 3; ++a) c[a] += by[a];
  return cells;
}

TEST(LatticeHull, CandidateCornersAndFacetHullMatchCgalOnEveryCorner) {
  std::mt19937 rng(7);
  // Random walks (dense rows: the grid of rows), up to a few hundred cells.
  for (int round = 0; round < 12; ++round) {
    std::set<LatticePoint> walk;
    LatticePoint c{0, 0, 0};
    const std::size_t size = 1 + rng() % 400;
    while (walk.size() < size) {
      walk.insert(c);
      c[rng() % 3] += (rng() % 2) ? 1 : -1;
    }
    expectMatchesOracle({walk.begin(), walk.end()}, "walk " + std::to_string(round));
  }
  // Sparse cells in a box: more (z, y) rows than 8 a cell, so rows come from sorted keys.
  for (int round = 0; round < 8; ++round) {
    std::set<LatticePoint> sparse;
    const std::size_t size = 1 + rng() % 40;
    while (sparse.size() < size)
      sparse.insert({std::int64_t(rng() % 30), std::int64_t(rng() % 30), std::int64_t(rng() % 30)});
    expectMatchesOracle({sparse.begin(), sparse.end()}, "sparse " + std::to_string(round));
  }
  // A slanted wall, thinned: many rows of one or two cells, and collinear corners on its faces.
  std::vector<LatticePoint> wall;
  for (std::int64_t y = 0; y < 25; ++y)
    for (std::int64_t z = 0; z < 20; ++z)
      if (rng() % 3 != 0) wall.push_back({(2 * y + 3 * z) / 5, y, z});
  expectMatchesOracle(wall, "slanted wall");
  // Layers with empty layers between them (z = 0, 3, 4, 9): planes holding one layer's face alone.
  std::vector<LatticePoint> layers;
  for (const std::int64_t z : {0, 3, 4, 9})
    for (int k = 0; k < 6; ++k) layers.push_back({std::int64_t(rng() % 8) - 4, std::int64_t(rng() % 8), z});
  expectMatchesOracle(layers, "layers with gaps");
  // One cell, one row, one flat layer, negative coordinates.
  expectMatchesOracle({{-5, -7, -9}}, "one cell");
  expectMatchesOracle({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 0, 0}}, "one row");
  std::vector<LatticePoint> flat;
  for (std::int64_t x = -3; x < 4; ++x)
    for (std::int64_t y = -2; y < 3; ++y)
      if ((x + y) % 3 != 0) flat.push_back({x, y, -1});
  expectMatchesOracle(flat, "one layer");
  // A wide box: corners up to 2^18 - 2 from the origin both ways, a span near 2^19 (128-bit
  // orientation tests).
  const std::int64_t reach = (std::int64_t(1) << 18) - 2;
  std::vector<LatticePoint> wide = shifted(layers, {-1000, 50, -7});
  wide.push_back({reach - 1, 3, 2});
  wide.push_back({-reach, reach / 2, reach - 1});
  expectMatchesOracle(wide, "span near 2^19");
}

// Beyond 2^18 from the origin the hull's offsets and volume would overflow 64 bits: facetHull says
// so; candidateCorners (CGAL's hull of an obstacle uses it, in doubles) still keeps every vertex, on
// spans of 2^22 that it cannot pack (every corner kept).
TEST(LatticeHull, TooWideForTheExactHullIsAnErrorAndItsCornersStillHoldEveryVertex) {
  for (const std::int64_t far : {std::int64_t(1) << 18, std::int64_t(1) << 22}) {
    SCOPED_TRACE("corner at " + std::to_string(far));
    const std::vector<LatticePoint> cells{{0, 0, 0}, {far - 1, 3, 2}, {-far / 3, far / 2, 5}, {7, -4, far / 4}};
    EXPECT_THROW(facetHull(cells), Error);
    const Mesh mesh = cgalHull(cells);
    const std::vector<LatticePoint> corners = candidateCorners(cells);
    const std::set<LatticePoint> kept(corners.begin(), corners.end());
    for (const auto v : mesh.vertices()) {
      const LatticePoint x = latticeVertex(mesh, v);
      EXPECT_TRUE(kept.count(x)) << x[0] << ' ' << x[1] << ' ' << x[2];
    }
  }
  EXPECT_NO_THROW(facetHull({{-(std::int64_t(1) << 18) + 1, 0, 0}, {(std::int64_t(1) << 18) - 2, 0, 0}}));
}

}  // namespace
}  // namespace hullmap::hulls::detail
