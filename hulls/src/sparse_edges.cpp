// Sparse edges: a sparse part grown in its own plane by a share of its point spacing (sparse_edges.hpp).
#include "hullmap/hulls/sparse_edges.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <Eigen/Eigenvalues>

#include "hullmap/core/constants.hpp"
#include "hullmap/core/convex_hull_2d.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/detail/lattice_hull.hpp"

namespace hullmap::hulls {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point3>;

void checkParams(double voxel_size, const SparseEdges& p) {
  if (!(voxel_size > 0.0) || !std::isfinite(voxel_size))
    throw Error::inParameter("voxel_size", "must be positive, got " + std::to_string(voxel_size));
  if (!(p.onset >= 0.0) || !std::isfinite(p.onset)) throw Error::inParameter("sparse_edges", "onset must be >= 0");
  if (!(p.factor >= 0.0) || !std::isfinite(p.factor)) throw Error::inParameter("sparse_edges", "factor must be >= 0");
  if (!(p.cap >= 0.0) || !std::isfinite(p.cap)) throw Error::inParameter("sparse_edges", "cap must be >= 0");
}

/// A part's plane: its hull vertices' mean, their principal axes (largest first) and whether the
/// part is flat.
struct Plane {
  Eigen::Vector3d mean;
  Eigen::Vector3d a, b;  ///< the two largest principal axes: the plane's directions
  bool flat = false;
};

Plane planeOf(const ObstaclePart& part) {
  const auto& v = part.hull.vertices;
  Plane plane;
  plane.mean = Eigen::Vector3d::Zero();
  for (const auto& p : v) plane.mean += p;
  plane.mean /= double(v.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : v) cov += (p - plane.mean) * (p - plane.mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);  // ascending eigenvalues
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& p : v) {
    const Eigen::Vector3d q = solver.eigenvectors().transpose() * (p - plane.mean);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const Eigen::Vector3d extent = hi - lo;
  plane.a = solver.eigenvectors().col(2);
  plane.b = solver.eigenvectors().col(1);
  plane.flat = part.flat || extent[0] < 0.25 * extent[1];
  return plane;
}

/// The area sparse_edges.hpp divides by the points: the plane's projection's for a flat part, half
/// the hull's surface for another.
double spreadArea(const ObstaclePart& part, const Plane& plane) {
  const auto& v = part.hull.vertices;
  if (plane.flat) {
    std::vector<Eigen::Vector2d> flat;
    flat.reserve(v.size());
    for (const auto& p : v) flat.emplace_back(plane.a.dot(p - plane.mean), plane.b.dot(p - plane.mean));
    const std::vector<Eigen::Vector2d> polygon = core::convexHull2d(std::move(flat));
    double twice = 0.0;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const auto& p = polygon[i];
      const auto& q = polygon[(i + 1) % polygon.size()];
      twice += p.x() * q.y() - q.x() * p.y();
    }
    return 0.5 * std::abs(twice);
  }
  double surface = 0.0;
  for (const auto& t : part.hull.triangles) surface += 0.5 * (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).norm();
  return 0.5 * surface;
}

/// The hull in a form that depends only on its geometry: CGAL's convex_hull_3 orders vertices and
/// faces by its containers' handles (addresses), and triangulates a face of 4 or more coplanar
/// vertices as its insertion order goes, so two processes can write the same hull differently.
/// Vertices sorted by (x, y, z); faces found as the triangles joined across coplanar edges (exact
/// predicates); each face a fan from its smallest vertex around its boundary; triangles sorted.
ConvexHull canonicalHull(const Mesh& mesh) {
  std::vector<Mesh::Vertex_index> order(mesh.vertices().begin(), mesh.vertices().end());
  std::sort(order.begin(), order.end(), [&](Mesh::Vertex_index a, Mesh::Vertex_index b) {
    const Point3 &p = mesh.point(a), &q = mesh.point(b);
    return std::make_tuple(p.x(), p.y(), p.z()) < std::make_tuple(q.x(), q.y(), q.z());
  });
  std::map<Mesh::Vertex_index, int> index;
  ConvexHull hull;
  for (const auto v : order) {
    index[v] = int(hull.vertices.size());
    const Point3& p = mesh.point(v);
    hull.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  // Faces: union of the triangles whose shared edge is flat (the far vertex of one lies in the
  // other's plane).
  std::vector<Mesh::Face_index> faces(mesh.faces().begin(), mesh.faces().end());
  std::map<Mesh::Face_index, std::size_t> face_number;
  for (std::size_t k = 0; k < faces.size(); ++k) face_number[faces[k]] = k;
  std::vector<std::size_t> parent(faces.size());
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  const auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto h : mesh.halfedges()) {
    const auto opposite = mesh.opposite(h);
    if (mesh.is_border(h) || mesh.is_border(opposite)) continue;
    const Point3& p = mesh.point(mesh.source(h));
    const Point3& q = mesh.point(mesh.target(h));
    const Point3& r = mesh.point(mesh.target(mesh.next(h)));
    const Point3& far = mesh.point(mesh.target(mesh.next(opposite)));
    if (CGAL::orientation(p, q, r, far) == CGAL::COPLANAR)
      parent[find(face_number[mesh.face(h)])] = find(face_number[mesh.face(opposite)]);
  }
  // Each face's boundary: its triangles' edges whose other side is another face, source -> target.
  std::map<std::size_t, std::map<int, int>> boundary;
  for (const auto h : mesh.halfedges()) {
    if (mesh.is_border(h)) continue;
    const std::size_t face = find(face_number[mesh.face(h)]);
    const auto opposite = mesh.opposite(h);
    if (!mesh.is_border(opposite) && find(face_number[mesh.face(opposite)]) == face) continue;
    boundary[face][index[mesh.source(h)]] = index[mesh.target(h)];
  }
  for (const auto& [face, next] : boundary) {
    const int first = next.begin()->first;  // the smallest vertex of the face
    std::vector<int> ring{first};
    for (int v = next.at(first); v != first && ring.size() <= next.size(); v = next.at(v)) ring.push_back(v);
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) hull.triangles.push_back({ring[0], ring[k], ring[k + 1]});
  }
  std::sort(hull.triangles.begin(), hull.triangles.end());
  return hull;
}

double growth(const ObstaclePart& part, const Plane& plane, double voxel_size, const SparseEdges& params) {
  const double spacing = std::sqrt(spreadArea(part, plane) / double(std::max<std::uint64_t>(1, part.point_weight)));
  const double grow = params.factor * (spacing - params.onset * voxel_size);
  if (!(grow > 0.0)) return 0.0;
  return std::min(grow, params.cap * voxel_size);
}

}  // namespace

double sparseEdgeGrowth(const ObstaclePart& part, double voxel_size, const SparseEdges& params) {
  checkParams(voxel_size, params);
  if (part.hull.vertices.size() < 4) return 0.0;
  return growth(part, planeOf(part), voxel_size, params);
}

double growSparseEdges(ObstaclePart& part, double voxel_size, const SparseEdges& params) {
  checkParams(voxel_size, params);
  if (part.hull.vertices.size() < 4) return 0.0;
  const Plane plane = planeOf(part);
  const double grow = growth(part, plane, voxel_size, params);
  if (grow <= 0.0) return 0.0;
  constexpr int kDirections = 12;
  std::vector<Point3> points;
  points.reserve(part.hull.vertices.size() * (kDirections + 1));
  for (const auto& p : part.hull.vertices) points.emplace_back(p.x(), p.y(), p.z());
  for (int k = 0; k < kDirections; ++k) {
    const double angle = 2.0 * kPi * k / kDirections;
    const Eigen::Vector3d step = grow * (std::cos(angle) * plane.a + std::sin(angle) * plane.b);
    for (const auto& p : part.hull.vertices) points.emplace_back(p.x() + step.x(), p.y() + step.y(), p.z() + step.z());
  }
  Mesh mesh;
  CGAL::convex_hull_3(points.begin(), points.end(), mesh);
  if (mesh.number_of_faces() < 4) return 0.0;  // degenerate: keep the part as it was
  part.hull = canonicalHull(mesh);
  part.aabb_min = part.aabb_max = part.hull.vertices.front();
  std::vector<Eigen::Vector2d> footprint;
  for (const auto& v : part.hull.vertices) {
    part.aabb_min = part.aabb_min.cwiseMin(v);
    part.aabb_max = part.aabb_max.cwiseMax(v);
    footprint.push_back(v.head<2>());
  }
  part.footprint.polygon = core::convexHull2d(std::move(footprint));
  part.footprint.z_min = part.aabb_min.z();
  part.footprint.z_max = part.aabb_max.z();
  std::tie(part.volume, part.centroid) = detail::volumeAndCentroid(part.hull, 0.5 * (part.aabb_min + part.aabb_max));
  return grow;
}

}  // namespace hullmap::hulls
