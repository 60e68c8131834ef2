#include "hullmap/clustering/coplanar_merge.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>

#include <Eigen/Eigenvalues>

#include "hullmap/core/error.hpp"
#include "hullmap/core/lattice.hpp"

namespace hullmap::clustering {

namespace {

/// The principal axes of the points `indices` picks: columns by ascending eigenvalue of their
/// covariance (Eigen::SelfAdjointEigenSolver); identity for fewer than 3 points.
Eigen::Matrix3d principalAxes(const std::vector<Eigen::Vector3d>& points, const std::vector<std::size_t>& indices) {
  if (indices.size() < 3) return Eigen::Matrix3d::Identity();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto i : indices) mean += points[i];
  mean /= double(indices.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto i : indices) {
    const Eigen::Vector3d d = points[i] - mean;
    covariance += d * d.transpose();
  }
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvectors();
}

/// Largest minus smallest value of axis . p over the points `indices` picks (0 for none).
double extentAlong(const std::vector<Eigen::Vector3d>& points, const std::vector<std::size_t>& indices,
                   const Eigen::Vector3d& axis) {
  if (indices.empty()) return 0.0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto i : indices) {
    const double v = axis.dot(points[i]);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  return hi - lo;
}

}  // namespace

double pointSetThickness(const std::vector<Eigen::Vector3d>& points, const std::vector<std::size_t>& indices) {
  if (indices.size() < 3) return 0.0;
  return extentAlong(points, indices, principalAxes(points, indices).col(0));
}

namespace {

// Each cluster joins the end of its chain of targets (targets are larger, so chains end), counted
// in `merge`; then the clusters are renumbered by first point.
void applyMerges(const std::vector<std::size_t>& target, const std::vector<std::vector<std::size_t>>& members,
                 DbscanResult& result, CoplanarMerge& merge) {
  const std::size_t k = target.size();
  std::vector<std::size_t> root(k);
  for (std::size_t c = 0; c < k; ++c) {
    std::size_t r = c;
    while (target[r] != r) r = target[r];
    root[c] = r;
    if (r != c) {
      ++merge.merged;
      merge.points += members[c].size();
    }
  }
  if (merge.merged == 0) return;
  // Renumber by first point.
  std::vector<std::int32_t> number(k, -1);
  std::int32_t next = 0;
  for (std::size_t i = 0; i < result.labels.size(); ++i) {
    const std::int32_t l = result.labels[i];
    if (l < 0) continue;
    const std::size_t r = root[std::size_t(l)];
    if (number[r] < 0) number[r] = next++;
    result.labels[i] = number[r];
  }
  result.cluster_sizes.assign(std::size_t(next), 0);
  for (const auto l : result.labels)
    if (l >= 0) ++result.cluster_sizes[std::size_t(l)];
}

}  // namespace

CoplanarMerge mergeCoplanarClusters(const std::vector<Eigen::Vector3d>& points, DbscanResult& result,
                                    const CoplanarMergeParams& params) {
  if (!(std::isfinite(params.reach) && params.reach > 0.0))
    throw Error::inParameter("reach", "must be finite and > 0, got " + std::to_string(params.reach));
  if (!(std::isfinite(params.thickness) && params.thickness > 0.0))
    throw Error::inParameter("thickness", "must be finite and > 0, got " + std::to_string(params.thickness));
  if (points.size() != result.labels.size()) throw Error::inParameter("labels", "one label per point expected");
  const std::size_t k = result.cluster_sizes.size();
  CoplanarMerge merge;
  if (k < 2) return merge;
  std::vector<std::vector<std::size_t>> members(k);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::int32_t l = result.labels[i];
    if (l < 0) continue;
    if (std::size_t(l) >= k) throw Error::inParameter("labels", "label " + std::to_string(l) + " without a cluster");
    if (!points[i].allFinite()) throw Error("coplanar merge: point " + std::to_string(i) + " is not finite");
    members[std::size_t(l)].push_back(i);
  }
  // The flat clusters (most clusters of a room are not: then nothing more to do).
  std::vector<std::size_t> flat;
  for (std::size_t b = 0; b < k; ++b)
    if (members[b].size() >= 3 && pointSetThickness(points, members[b]) <= params.thickness) flat.push_back(b);
  if (flat.empty()) return merge;
  // Clustered points in cells of side 2 reach: a point within 2 reach lies in one of the 27 cells around.
  const double inv = 0.5 / params.reach;
  const auto cellOf = [&](const Eigen::Vector3d& p) {
    return std::array<std::int64_t, 3>{std::int64_t(std::floor(p.x() * inv)), std::int64_t(std::floor(p.y() * inv)),
                                       std::int64_t(std::floor(p.z() * inv))};
  };
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> grid;
  for (const auto& cluster : members)
    for (const auto i : cluster) {
      const auto c = cellOf(points[i]);
      grid[core::hashCell(c[0], c[1], c[2])].push_back(i);
    }
  const double reach2 = params.reach * params.reach, around2 = 4.0 * reach2;
  const auto larger = [&](std::size_t a, std::size_t b) {  // A may take B
    return members[a].size() > members[b].size() || (members[a].size() == members[b].size() && a < b);
  };
  std::vector<std::size_t> target(k);
  std::iota(target.begin(), target.end(), std::size_t(0));
  std::vector<std::vector<std::size_t>> near(k);  // A's points within 2 reach of B's
  std::vector<char> adjacent(k, 0);               // some point of A within reach of B's
  std::vector<char> seen(points.size(), 0);
  std::vector<double> gap2(points.size(), 0.0);  // a near point's squared distance to B
  for (const std::size_t b : flat) {
    for (auto& n : near) n.clear();
    std::fill(adjacent.begin(), adjacent.end(), 0);
    for (const auto i : members[b]) {
      const auto c = cellOf(points[i]);
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (std::int64_t dy = -1; dy <= 1; ++dy)
          for (std::int64_t dz = -1; dz <= 1; ++dz) {
            const auto hit = grid.find(core::hashCell(c[0] + dx, c[1] + dy, c[2] + dz));
            if (hit == grid.end()) continue;
            for (const auto j : hit->second) {
              const auto a = std::size_t(result.labels[j]);
              if (a == b || !larger(a, b)) continue;
              const double d2 = (points[j] - points[i]).squaredNorm();
              if (d2 <= reach2) adjacent[a] = 1;
              if (d2 > around2) continue;
              if (!seen[j]) {
                seen[j] = 1;
                near[a].push_back(j);
                gap2[j] = d2;
              } else {
                gap2[j] = std::min(gap2[j], d2);
              }
            }
          }
    }
    std::size_t best = b, best_count = 0;
    for (std::size_t a = 0; a < k; ++a) {
      for (const auto j : near[a]) seen[j] = 0;
      const std::size_t count = near[a].size();
      if (!adjacent[a] || count < 3 || count <= best_count) continue;
      // A's points nearest to B, as many as B has (at least 3): the surface around B.
      std::vector<std::size_t>& around = near[a];
      const std::size_t m = std::min(around.size(), std::max<std::size_t>(3, members[b].size()));
      std::partial_sort(
          around.begin(), around.begin() + std::ptrdiff_t(m), around.end(),
          [&](std::size_t x, std::size_t y) { return gap2[x] < gap2[y] || (gap2[x] == gap2[y] && x < y); });
      std::vector<std::size_t> both = members[b];
      both.insert(both.end(), around.begin(), around.begin() + std::ptrdiff_t(m));
      const Eigen::Matrix3d axes = principalAxes(points, both);
      if (extentAlong(points, both, axes.col(0)) > params.thickness) continue;
      // A's surface around B spans the plane, not only a line in it (a wall's foot by a patch of
      // floor: the foot's row of voxels lies in the floor's plane, the wall does not).
      around.resize(m);
      if (extentAlong(points, around, axes.col(1)) < 2.0 * params.thickness) continue;
      best = a;
      best_count = count;
    }
    target[b] = best;
  }
  applyMerges(target, members, result, merge);
  return merge;
}

}  // namespace hullmap::clustering
