#include "hullmap/clustering/obstacles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <tbb/parallel_for.h>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/mapper/error.hpp"

namespace hullmap::clustering {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point3>;

/// Integer corner of the voxel lattice: corner (i, j, k) is at origin + (i, j, k) * voxel_size.
struct CornerKey {
  std::int64_t a;
  std::int64_t b;
  bool operator==(const CornerKey& o) const { return a == o.a && b == o.b; }
};
struct CornerKeyHash {
  std::size_t operator()(const CornerKey& k) const {
    return std::hash<std::int64_t>()(k.a * 73856093LL) ^ std::hash<std::int64_t>()(k.b * 19349663LL);
  }
};
using Range = std::pair<std::int64_t, std::int64_t>;
using ColumnExtremes = std::unordered_map<CornerKey, Range, CornerKeyHash>;

void widen(ColumnExtremes& columns, CornerKey key, std::int64_t lo, std::int64_t hi) {
  auto [it, inserted] = columns.try_emplace(key, lo, hi);
  if (!inserted) {
    it->second.first = std::min(it->second.first, lo);
    it->second.second = std::max(it->second.second, hi);
  }
}

/// Corners that can be vertices of the hull of all voxel corners: a corner strictly between two
/// others on an axis-parallel line is not extreme, so only each line's two ends are kept, for the
/// lines along x, y and z. Exact (integer lattice), never drops a hull vertex.
std::vector<std::array<std::int64_t, 3>> candidateCorners(const std::vector<std::array<std::int64_t, 3>>& cells) {
  ColumnExtremes along_x, along_y, along_z;
  for (const auto& c : cells) {
    for (int dy = 0; dy < 2; ++dy)
      for (int dz = 0; dz < 2; ++dz) widen(along_x, {c[1] + dy, c[2] + dz}, c[0], c[0] + 1);
    for (int dx = 0; dx < 2; ++dx)
      for (int dz = 0; dz < 2; ++dz) widen(along_y, {c[0] + dx, c[2] + dz}, c[1], c[1] + 1);
    for (int dx = 0; dx < 2; ++dx)
      for (int dy = 0; dy < 2; ++dy) widen(along_z, {c[0] + dx, c[1] + dy}, c[2], c[2] + 1);
  }
  auto isEnd = [](const ColumnExtremes& columns, CornerKey key, std::int64_t v) {
    const auto it = columns.find(key);
    return it != columns.end() && (it->second.first == v || it->second.second == v);
  };
  std::vector<std::array<std::int64_t, 3>> out;
  for (const auto& [key, range] : along_z) {
    for (const std::int64_t z : {range.first, range.second}) {
      const std::int64_t x = key.a, y = key.b;
      if (isEnd(along_x, {y, z}, x) && isEnd(along_y, {x, z}, y)) out.push_back({x, y, z});
    }
  }
  return out;
}

Obstacle wrapCluster(int id, const std::vector<std::size_t>& members, const std::vector<Eigen::Vector3d>& centers,
                     const std::vector<std::uint32_t>& weights, double voxel_size) {
  Obstacle obstacle;
  obstacle.id = id;
  obstacle.voxel_count = members.size();
  const double half = 0.5 * voxel_size;
  // Lattice origin: the lower corner of the first voxel; every voxel's index is its offset from it.
  const Eigen::Vector3d origin = centers[members.front()] - Eigen::Vector3d::Constant(half);
  std::vector<std::array<std::int64_t, 3>> cells;
  cells.reserve(members.size());
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const std::size_t i : members) {
    obstacle.point_weight += weights.empty() ? 1 : weights[i];
    const Eigen::Vector3d rel = (centers[i] - origin) / voxel_size - Eigen::Vector3d::Constant(0.5);
    cells.push_back({std::llround(rel.x()), std::llround(rel.y()), std::llround(rel.z())});
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

  std::map<Mesh::Vertex_index, int> index;
  for (const auto v : mesh.vertices()) {
    const Point3& p = mesh.point(v);
    index[v] = int(obstacle.hull.vertices.size());
    obstacle.hull.vertices.push_back(cornerPoint({std::int64_t(p.x()), std::int64_t(p.y()), std::int64_t(p.z())}));
  }
  for (const auto f : mesh.faces()) {
    std::vector<int> ring;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) ring.push_back(index[v]);
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) obstacle.hull.triangles.push_back({ring[0], ring[k], ring[k + 1]});
  }

  // Volume and centroid by the divergence theorem on the outward triangles (tetrahedra from a
  // reference point inside the hull, for accuracy away from the origin).
  const Eigen::Vector3d ref = obstacle.hull.vertices.front();
  double volume = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const auto& t : obstacle.hull.triangles) {
    const Eigen::Vector3d a = obstacle.hull.vertices[t[0]] - ref;
    const Eigen::Vector3d b = obstacle.hull.vertices[t[1]] - ref;
    const Eigen::Vector3d c = obstacle.hull.vertices[t[2]] - ref;
    const double v = a.dot(b.cross(c)) / 6.0;
    volume += v;
    moment += v * (a + b + c) / 4.0;
  }
  obstacle.volume = volume;
  obstacle.centroid = volume > 0 ? Eigen::Vector3d(ref + moment / volume) : Eigen::Vector3d(0.5 * (lo + hi));
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
  obstacle.footprint.polygon = convexHull2d(std::move(flat));
  obstacle.footprint.z_min = obstacle.aabb_min.z();
  obstacle.footprint.z_max = obstacle.aabb_max.z();
  return obstacle;
}

double cross2(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

}  // namespace

std::vector<Eigen::Vector2d> convexHull2d(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross2(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross2(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

std::vector<Obstacle> buildObstacles(const std::vector<Eigen::Vector3d>& centers,
                                     const std::vector<std::uint32_t>& weights,
                                     const std::vector<std::int32_t>& labels, double voxel_size) {
  if (!(voxel_size > 0) || !std::isfinite(voxel_size))
    throw Error("buildObstacles: voxel_size must be positive, got " + std::to_string(voxel_size));
  if (labels.size() != centers.size())
    throw Error("buildObstacles: " + std::to_string(labels.size()) + " labels for " +
                std::to_string(centers.size()) + " voxels");
  if (!weights.empty() && weights.size() != centers.size())
    throw Error("buildObstacles: " + std::to_string(weights.size()) + " weights for " +
                std::to_string(centers.size()) + " voxels");
  std::map<std::int32_t, std::vector<std::size_t>> clusters;
  for (std::size_t i = 0; i < centers.size(); ++i) {
    if (labels[i] == kNoise) continue;
    if (labels[i] < 0) throw Error("buildObstacles: invalid label " + std::to_string(labels[i]));
    if (!centers[i].allFinite()) throw Error("buildObstacles: non-finite voxel centre at index " + std::to_string(i));
    clusters[labels[i]].push_back(i);
  }
  std::vector<std::pair<std::int32_t, std::vector<std::size_t>>> work(clusters.begin(), clusters.end());
  std::vector<Obstacle> obstacles(work.size());
  tbb::parallel_for(std::size_t(0), work.size(), [&](std::size_t k) {
    obstacles[k] = wrapCluster(work[k].first, work[k].second, centers, weights, voxel_size);
  });
  return obstacles;
}

}  // namespace hullmap::clustering
