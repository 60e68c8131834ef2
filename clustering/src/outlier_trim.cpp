#include "hullmap/clustering/outlier_trim.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "hullmap/core/error.hpp"
#include "cell_hash.hpp"

namespace hullmap::clustering {
namespace {

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

struct CellKeyHash {
  std::size_t operator()(const CellKey& c) const { return static_cast<std::size_t>(detail::hashCell(c.x, c.y, c.z)); }
};

/// Squared distance from p to the segment q s (s != q).
double segmentDistance2(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& s) {
  const Eigen::Vector3d d = s - q;
  if (d.squaredNorm() == 0.0) return (q - p).squaredNorm();
  const double t = std::clamp((p - q).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (q + t * d - p).squaredNorm();
}

}  // namespace

OutlierTrim trimOutliers(const std::vector<Eigen::Vector3d>& points, DbscanResult& result,
                         const std::vector<Eigen::Vector3d>& support, const OutlierTrimParams& params) {
  if (!(std::isfinite(params.radius) && params.radius > 0.0)) throw Error::inParameter("radius", "must be finite and > 0");
  if (!(std::isfinite(params.reach) && params.reach >= params.radius))
    throw Error::inParameter("reach", "must be finite and >= radius");
  const std::size_t n = points.size();
  if (result.labels.size() != n || result.core.size() != n)
    throw Error::inParameter("labels", std::to_string(result.labels.size()) + " labels and " +
                                           std::to_string(result.core.size()) + " core flags for " + std::to_string(n) +
                                           " points");
  for (std::size_t i = 0; i < n; ++i)
    if (!points[i].allFinite()) throw Error::inParameter("points", "point " + std::to_string(i) + " is not finite");
  for (std::size_t i = 0; i < support.size(); ++i)
    if (!support[i].allFinite()) throw Error::inParameter("support", "point " + std::to_string(i) + " is not finite");
  OutlierTrim out;

  // Candidates first: most maps have none, and then no grid is built.
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < n; ++i)
    if (result.labels[i] >= 0 && !result.core[i]) candidates.push_back(i);
  if (candidates.empty()) return out;

  // One grid of cells of side reach over both sets: index k < n is points[k], else support[k - n].
  const double side = params.reach * (1.0 + 1e-9);
  const auto at = [&](std::size_t k) -> const Eigen::Vector3d& { return k < n ? points[k] : support[k - n]; };
  const auto keyOf = [&](const Eigen::Vector3d& p) {
    return CellKey{static_cast<std::int64_t>(std::floor(p.x() / side)), static_cast<std::int64_t>(std::floor(p.y() / side)),
                   static_cast<std::int64_t>(std::floor(p.z() / side))};
  };
  std::unordered_map<CellKey, std::vector<std::size_t>, CellKeyHash> grid;
  for (std::size_t k = 0; k < n + support.size(); ++k) grid[keyOf(at(k))].push_back(k);

  const double radius2 = params.radius * params.radius;
  const double reach2 = params.reach * params.reach;
  std::vector<std::size_t> drop;
  std::vector<std::size_t> near;  // supporting points within reach of the candidate
  for (const std::size_t i : candidates) {
    const Eigen::Vector3d& p = points[i];
    const CellKey c = keyOf(p);
    bool alone = true;
    near.clear();
    for (std::int64_t dx = -1; dx <= 1 && alone; ++dx)
      for (std::int64_t dy = -1; dy <= 1 && alone; ++dy)
        for (std::int64_t dz = -1; dz <= 1 && alone; ++dz) {
          const auto cell = grid.find(CellKey{c.x + dx, c.y + dy, c.z + dz});
          if (cell == grid.end()) continue;
          for (const std::size_t k : cell->second) {
            if (k == i) continue;
            const double d2 = (at(k) - p).squaredNorm();
            if (d2 <= radius2) {
              alone = false;
              break;
            }
            if (d2 <= reach2 && (k >= n || result.labels[k] >= 0)) near.push_back(k);
          }
        }
    if (!alone) continue;
    // In the order of the indices, so that the answer does not depend on the grid's layout.
    std::sort(near.begin(), near.end());
    bool on_structure = false;
    for (std::size_t a = 0; a < near.size() && !on_structure; ++a)
      for (std::size_t b = a + 1; b < near.size() && !on_structure; ++b)
        on_structure = segmentDistance2(p, at(near[a]), at(near[b])) <= radius2;
    if (!on_structure) drop.push_back(i);
  }
  for (const std::size_t i : drop) {
    --result.cluster_sizes[static_cast<std::size_t>(result.labels[i])];
    result.labels[i] = kNoise;
  }
  result.noise += drop.size();
  out.dropped = drop.size();
  return out;
}

}  // namespace hullmap::clustering
