#include "hullmap/hulls/obstacles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <tuple>
#include <utility>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/convex_hull_2d.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/detail/lattice_hull.hpp"

namespace hullmap::hulls {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point3>;

using Range = std::pair<std::int64_t, std::int64_t>;

}  // namespace

namespace {
using detail::candidateCorners;

/// A hull on the integer lattice of voxel corners.
struct LatticeHull {
  std::vector<std::array<std::int64_t, 3>> vertices;
  std::vector<std::array<int, 3>> triangles;  ///< counter-clockwise seen from outside
};

/// The hull in a form that depends only on the polytope, not on how CGAL happened to build it:
/// CGAL triangulates each flat facet (a lattice hull has many: every face of a box) in an order
/// that varies from run to run with memory addresses, and lists vertices in its own order. Here
/// each facet (the triangles of one plane, exact on the lattice) is traced as its boundary loop,
/// vertices lying on a straight part of the loop (on an edge of the polytope) are dropped, and the
/// loop is fanned from its smallest vertex; vertices are sorted lexicographically, triangles too.
LatticeHull canonical(const LatticeHull& hull, int id) {
  using Vec = std::array<std::int64_t, 3>;
  const auto sub = [](const Vec& a, const Vec& b) { return Vec{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  const auto cross = [](const Vec& a, const Vec& b) {
    return Vec{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  const auto fail = [&](const char* what) -> void {
    throw Error("buildObstacles: hull of cluster " + std::to_string(id) + ": " + what);
  };
  // Facets: triangles grouped by their plane (primitive outward normal and offset), sorted by it.
  using Plane = std::array<std::int64_t, 4>;
  std::vector<std::pair<Plane, std::array<int, 3>>> by_plane;
  by_plane.reserve(hull.triangles.size());
  for (const auto& t : hull.triangles) {
    const Vec& a = hull.vertices[std::size_t(t[0])];
    Vec n = cross(sub(hull.vertices[std::size_t(t[1])], a), sub(hull.vertices[std::size_t(t[2])], a));
    const std::int64_t g = std::gcd(std::gcd(std::abs(n[0]), std::abs(n[1])), std::abs(n[2]));
    if (g == 0) fail("a triangle of zero area");
    for (auto& c : n) c /= g;
    by_plane.push_back({{n[0], n[1], n[2], n[0] * a[0] + n[1] * a[1] + n[2] * a[2]}, t});
  }
  std::sort(by_plane.begin(), by_plane.end());
  std::vector<std::vector<int>> loops;
  std::vector<std::pair<int, int>> edges, next;  // sorted; next: the boundary edges (u, v)
  for (std::size_t begin = 0; begin < by_plane.size();) {
    std::size_t end = begin;
    while (end < by_plane.size() && by_plane[end].first == by_plane[begin].first) ++end;
    const Plane& plane = by_plane[begin].first;
    // Boundary edges are those of one triangle whose reverse is in none; they run counter-clockwise.
    edges.clear();
    for (std::size_t f = begin; f < end; ++f)
      for (int k = 0; k < 3; ++k)
        edges.push_back({by_plane[f].second[std::size_t(k)], by_plane[f].second[std::size_t((k + 1) % 3)]});
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    next.clear();
    for (const auto& [u, v] : edges)
      if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(v, u))) {
        if (!next.empty() && next.back().first == u) fail("a facet whose boundary is not one loop");
        next.push_back({u, v});
      }
    if (next.empty()) fail("a facet whose boundary is not one loop");
    const auto after = [&](int u) {
      const auto it = std::lower_bound(next.begin(), next.end(), std::make_pair(u, std::numeric_limits<int>::min()));
      return it != next.end() && it->first == u ? std::optional<int>(it->second) : std::nullopt;
    };
    std::vector<int> loop{next.front().first};
    while (loop.size() <= next.size()) {
      const std::optional<int> v = after(loop.back());
      if (!v) fail("a facet whose boundary is not one loop");
      if (*v == loop.front()) break;
      loop.push_back(*v);
    }
    if (loop.size() != next.size()) fail("a facet whose boundary is not one loop");
    std::vector<int> corners;
    const Vec normal{plane[0], plane[1], plane[2]};
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Vec& prev = hull.vertices[std::size_t(loop[(k + loop.size() - 1) % loop.size()])];
      const Vec& here = hull.vertices[std::size_t(loop[k])];
      const Vec& following = hull.vertices[std::size_t(loop[(k + 1) % loop.size()])];
      const Vec turn = cross(sub(here, prev), sub(following, here));
      if (turn[0] * normal[0] + turn[1] * normal[1] + turn[2] * normal[2] != 0) corners.push_back(loop[k]);
    }
    if (corners.size() < 3) fail("a facet of fewer than three corners");
    loops.push_back(std::move(corners));
    begin = end;
  }
  // Vertices in lexicographic order, then each loop fanned from its smallest vertex.
  std::vector<int> used;
  for (const auto& loop : loops) used.insert(used.end(), loop.begin(), loop.end());
  std::sort(used.begin(), used.end(), [&](int a, int b) {
    return hull.vertices[std::size_t(a)] < hull.vertices[std::size_t(b)] ||
           (hull.vertices[std::size_t(a)] == hull.vertices[std::size_t(b)] && a < b);
  });
  used.erase(std::unique(used.begin(), used.end()), used.end());
  LatticeHull out;
  std::vector<int> renumber(hull.vertices.size(), -1);
  for (const int v : used) {
    renumber[std::size_t(v)] = int(out.vertices.size());
    out.vertices.push_back(hull.vertices[std::size_t(v)]);
  }
  for (auto& loop : loops) {
    for (int& v : loop) v = renumber[std::size_t(v)];
    std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
    for (std::size_t k = 1; k + 1 < loop.size(); ++k) out.triangles.push_back({loop[0], loop[k], loop[k + 1]});
  }
  std::sort(out.triangles.begin(), out.triangles.end());
  return out;
}

}  // namespace

namespace detail {

std::pair<double, Eigen::Vector3d> volumeAndCentroid(const ConvexHull& hull, const Eigen::Vector3d& fallback) {
  // Tetrahedra from a reference point on the hull, for accuracy away from the origin.
  const Eigen::Vector3d ref = hull.vertices.front();
  double volume = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const auto& t : hull.triangles) {
    const Eigen::Vector3d a = hull.vertices[t[0]] - ref;
    const Eigen::Vector3d b = hull.vertices[t[1]] - ref;
    const Eigen::Vector3d c = hull.vertices[t[2]] - ref;
    const double v = a.dot(b.cross(c)) / 6.0;
    volume += v;
    moment += v * (a + b + c) / 4.0;
  }
  return {volume, volume > 0 ? Eigen::Vector3d(ref + moment / volume) : fallback};
}

Obstacle wrapCluster(int id, const std::vector<std::size_t>& members, const std::vector<Eigen::Vector3d>& centers,
                     const std::vector<std::uint32_t>& weights, double voxel_size) {
  Obstacle obstacle;
  obstacle.id = id;
  obstacle.voxel_count = members.size();
  const double half = 0.5 * voxel_size;
  // Lattice origin: the lower corner of the lexicographically smallest voxel centre (not the first
  // member: the corners' last bits must not depend on the order of the voxels); every voxel's index
  // is its offset from it.
  const std::size_t anchor = *std::min_element(members.begin(), members.end(), [&](std::size_t a, std::size_t b) {
    const Eigen::Vector3d& p = centers[a];
    const Eigen::Vector3d& q = centers[b];
    return std::tie(p.x(), p.y(), p.z()) < std::tie(q.x(), q.y(), q.z());
  });
  const Eigen::Vector3d origin = centers[anchor] - Eigen::Vector3d::Constant(half);
  std::vector<std::array<std::int64_t, 3>> cells;
  cells.reserve(members.size());
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const std::size_t i : members) {
    obstacle.point_weight += weights.empty() ? 1 : weights[i];
    cells.push_back(latticeIndex(centers[i], origin, voxel_size));
    lo = lo.cwiseMin(centers[i] - Eigen::Vector3d::Constant(half));
    hi = hi.cwiseMax(centers[i] + Eigen::Vector3d::Constant(half));
  }
  // Corners on the lattice can differ from centre +- half by an ulp: containment holds to ~1e-15
  // relative, which is what the tests allow.
  auto cornerPoint = [&](const std::array<std::int64_t, 3>& c) {
    return Eigen::Vector3d(origin + Eigen::Vector3d(double(c[0]), double(c[1]), double(c[2])) * voxel_size);
  };

  // The hull is computed on the integer lattice, where coplanar and collinear corners are exactly
  // so (scaled doubles are not: rounding would leave sliver triangles with meaningless normals).
  std::vector<Point3> points;
  for (const auto& c : candidateCorners(cells)) points.emplace_back(double(c[0]), double(c[1]), double(c[2]));
  Mesh mesh;
  CGAL::convex_hull_3(points.begin(), points.end(), mesh);
  if (mesh.number_of_faces() == 0) throw Error("buildObstacles: degenerate hull for cluster " + std::to_string(id));

  LatticeHull lattice;
  std::map<Mesh::Vertex_index, int> index;
  for (const auto v : mesh.vertices()) {
    const Point3& p = mesh.point(v);
    index[v] = int(lattice.vertices.size());
    lattice.vertices.push_back({std::int64_t(p.x()), std::int64_t(p.y()), std::int64_t(p.z())});
  }
  for (const auto f : mesh.faces()) {
    std::vector<int> ring;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) ring.push_back(index[v]);
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) lattice.triangles.push_back({ring[0], ring[k], ring[k + 1]});
  }
  lattice = canonical(lattice, id);
  for (const auto& v : lattice.vertices) obstacle.hull.vertices.push_back(cornerPoint(v));
  obstacle.hull.triangles = lattice.triangles;

  std::tie(obstacle.volume, obstacle.centroid) = volumeAndCentroid(obstacle.hull, 0.5 * (lo + hi));
  obstacle.aabb_min = lo;
  obstacle.aabb_max = hi;
  for (const auto& v : obstacle.hull.vertices) {
    obstacle.aabb_min = obstacle.aabb_min.cwiseMin(v);
    obstacle.aabb_max = obstacle.aabb_max.cwiseMax(v);
  }

  // Footprint: per x line of the corner lattice, only the two y ends can be 2D hull vertices.
  std::map<std::int64_t, Range> along_y;
  for (const auto& c : cells) {
    for (int dx = 0; dx < 2; ++dx) {
      auto [it, inserted] = along_y.try_emplace(c[0] + dx, c[1], c[1] + 1);
      if (!inserted) {
        it->second.first = std::min(it->second.first, c[1]);
        it->second.second = std::max(it->second.second, c[1] + 1);
      }
    }
  }
  std::vector<Eigen::Vector2d> flat;
  for (const auto& [x, range] : along_y) {
    flat.push_back(cornerPoint({x, range.first, 0}).head<2>());
    flat.push_back(cornerPoint({x, range.second, 0}).head<2>());
  }
  obstacle.footprint.polygon = core::convexHull2d(std::move(flat));
  obstacle.footprint.z_min = obstacle.aabb_min.z();
  obstacle.footprint.z_max = obstacle.aabb_max.z();
  return obstacle;
}

}  // namespace detail

bool hullContains(const ConvexHull& hull, const Eigen::Vector3d& p) {
  if (hull.triangles.empty()) return false;
  double scale = 1.0;
  for (const auto& v : hull.vertices) scale = std::max(scale, v.cwiseAbs().maxCoeff());
  for (const auto& t : hull.triangles) {
    const Eigen::Vector3d& a = hull.vertices[std::size_t(t[0])];
    const Eigen::Vector3d n = (hull.vertices[std::size_t(t[1])] - a).cross(hull.vertices[std::size_t(t[2])] - a);
    const double length = n.norm();
    if (!(length > 0.0)) continue;  // a sliver triangle bounds nothing its neighbours do not
    if (n.dot(p - a) / length > 1e-9 * scale) return false;
  }
  return true;
}

std::vector<Obstacle> buildObstacles(const std::vector<Eigen::Vector3d>& centers,
                                     const std::vector<std::uint32_t>& weights, const std::vector<std::int32_t>& labels,
                                     double voxel_size) {
  if (!(voxel_size > 0) || !std::isfinite(voxel_size))
    throw Error::inParameter("voxel_size", "must be positive, got " + std::to_string(voxel_size));
  if (labels.size() != centers.size())
    throw Error("buildObstacles: " + std::to_string(labels.size()) + " labels for " + std::to_string(centers.size()) +
                " voxels");
  if (!weights.empty() && weights.size() != centers.size())
    throw Error("buildObstacles: " + std::to_string(weights.size()) + " weights for " + std::to_string(centers.size()) +
                " voxels");
  std::map<std::int32_t, std::vector<std::size_t>> clusters;
  for (std::size_t i = 0; i < centers.size(); ++i) {
    if (labels[i] == clustering::kNoise) continue;
    if (labels[i] < 0) throw Error("buildObstacles: invalid label " + std::to_string(labels[i]));
    if (!centers[i].allFinite()) throw Error("buildObstacles: non-finite voxel centre at index " + std::to_string(i));
    clusters[labels[i]].push_back(i);
  }
  std::vector<std::pair<std::int32_t, std::vector<std::size_t>>> work(clusters.begin(), clusters.end());
  std::vector<Obstacle> obstacles(work.size());
  tbb::parallel_for(std::size_t(0), work.size(), [&](std::size_t k) {
    obstacles[k] = detail::wrapCluster(work[k].first, work[k].second, centers, weights, voxel_size);
  });
  return obstacles;
}

}  // namespace hullmap::hulls
