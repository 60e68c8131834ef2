#pragma once
// Independent exact geometry for the collision tests: point-polytope distance by half-spaces and
// triangles, segment-polytope distance by golden-section search on the convex function
// s -> dist(a + s (b - a), P). Shares no code with the library.

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include <Eigen/Geometry>

#include "hullmap/hulls/obstacles.hpp"

namespace hullmap::test {

using V3 = Eigen::Vector3d;

inline double pointSegment(const V3& p, const V3& a, const V3& b) {
  const V3 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (a + t * d - p).norm();
}

inline double pointTriangle(const V3& p, const V3& a, const V3& b, const V3& c) {
  const V3 n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  if (n2 > 0) {
    const V3 q = p - n * (n.dot(p - a) / n2);  // projection onto the plane
    const double u = (b - q).cross(c - q).dot(n), v = (c - q).cross(a - q).dot(n), w = (a - q).cross(b - q).dot(n);
    if (u >= 0 && v >= 0 && w >= 0) return std::abs(n.dot(p - a)) / std::sqrt(n2);
  }
  return std::min({pointSegment(p, a, b), pointSegment(p, b, c), pointSegment(p, c, a)});
}

inline double pointHull(const V3& p, const hulls::ConvexHull& hull) {
  bool inside = true;
  for (const auto& t : hull.triangles) {
    const V3& a = hull.vertices[t[0]];
    const V3 n = (hull.vertices[t[1]] - a).cross(hull.vertices[t[2]] - a);
    inside = inside && n.dot(p - a) <= 0;
  }
  if (inside) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : hull.triangles)
    best = std::min(best, pointTriangle(p, hull.vertices[t[0]], hull.vertices[t[1]], hull.vertices[t[2]]));
  return best;
}

inline double segmentHull(const V3& a, const V3& b, const hulls::ConvexHull& hull) {
  auto f = [&](double s) { return pointHull(a + s * (b - a), hull); };
  double lo = 0, hi = 1;
  const double g = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 90; ++i) {
    if (f1 <= f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = f(x2);
    }
  }
  return std::min({f(0.0), f(1.0), f1, f2});
}

/// Distance between a segment and an axis-aligned box: golden-section search on the convex
/// s -> dist(a + s (b - a), box), the point-box distance by clamping.
inline double segmentBox(const V3& a, const V3& b, const V3& lo, const V3& hi) {
  auto f = [&](double s) {
    const V3 p = a + s * (b - a);
    return (p - p.cwiseMax(lo).cwiseMin(hi)).norm();
  };
  double l = 0, h = 1;
  const double g = (std::sqrt(5.0) - 1) / 2;
  for (int i = 0; i < 90; ++i) {
    const double x1 = h - g * (h - l), x2 = l + g * (h - l);
    (f(x1) <= f(x2) ? h : l) = (f(x1) <= f(x2) ? x2 : x1);
  }
  return std::min({f(0.0), f(1.0), f(0.5 * (l + h))});
}

/// A lower bound of the distance between a segment and a hull: the gap between their boxes.
inline double boxGap(const V3& a, const V3& b, const hulls::ConvexHull& hull) {
  V3 lo = hull.vertices[0], hi = hull.vertices[0];
  for (const auto& v : hull.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const V3 gap = (lo - a.cwiseMax(b)).cwiseMax(a.cwiseMin(b) - hi).cwiseMax(V3::Zero());
  return gap.norm();
}

/// A random rigid motion applied to a hull (rotations make faces that no lattice would).
inline hulls::ConvexHull moved(const hulls::ConvexHull& hull, std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> u(-1, 1);
  const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
  const V3 shift(u(rng) * spread, u(rng) * spread, u(rng) * spread);
  hulls::ConvexHull out = hull;
  for (auto& v : out.vertices) v = q * v + shift;
  return out;
}

/// Voxel blobs (random walks on a lattice) labelled 0..clusters-1, centred near the origin.
struct VoxelBlobs {
  std::vector<V3> centers;
  std::vector<std::uint32_t> weights;
  std::vector<std::int32_t> labels;
};

inline VoxelBlobs randomBlobs(std::mt19937& rng, int clusters, int max_voxels, double size, int extent) {
  VoxelBlobs b;
  for (int label = 0; label < clusters; ++label) {
    std::set<std::array<int, 3>> cells;
    std::array<int, 3> at{int(rng() % (2 * extent)) - extent, int(rng() % (2 * extent)) - extent, int(rng() % extent)};
    const int n = 1 + int(rng() % max_voxels);
    while (int(cells.size()) < n) {
      cells.insert(at);
      at[rng() % 3] += (rng() % 2) ? 1 : -1;
    }
    for (const auto& c : cells) {
      b.centers.push_back(V3(c[0] + 0.5, c[1] + 0.5, c[2] + 0.5) * size);
      b.weights.push_back(1);
      b.labels.push_back(label);
    }
  }
  return b;
}

}  // namespace hullmap::test
