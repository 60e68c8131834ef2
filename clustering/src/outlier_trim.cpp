#include "hullmap/clustering/outlier_trim.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include <Eigen/Eigenvalues>

#include "hullmap/core/convex_hull_2d.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/core/lattice.hpp"

namespace hullmap::clustering {
namespace {

using core::Cell;
using core::CellHash;

/// Whether p stands off the flat patch that the points q sample (see trimOutliers): q is at most
/// `radius` thick along its least-variance axis, p lies farther than `radius` outside that slab, and
/// p's projection on the patch's plane lies in the convex hull of q's projections.
bool offAFlatPatch(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& q, double radius) {
  if (q.size() < 3) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& x : q) mean += x;
  mean /= double(q.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& x : q) cov += (x - mean) * (x - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> pca(cov);
  const Eigen::Vector3d n = pca.eigenvectors().col(0), u = pca.eigenvectors().col(1), v = pca.eigenvectors().col(2);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& x : q) {
    lo = std::min(lo, n.dot(x - mean));
    hi = std::max(hi, n.dot(x - mean));
  }
  if (hi - lo > radius) return false;
  const double offset = n.dot(p - mean);
  if (offset <= hi + radius && offset >= lo - radius) return false;
  std::vector<Eigen::Vector2d> flat;
  flat.reserve(q.size());
  for (const auto& x : q) flat.emplace_back(u.dot(x - mean), v.dot(x - mean));
  const std::vector<Eigen::Vector2d> hull = core::convexHull2d(std::move(flat));
  if (hull.size() < 3) return false;
  const Eigen::Vector2d at(u.dot(p - mean), v.dot(p - mean));
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const Eigen::Vector2d a = hull[k], b = hull[(k + 1) % hull.size()];
    const Eigen::Vector2d e = b - a, w = at - a;
    if (e.x() * w.y() - e.y() * w.x() < 0.0) return false;  // right of a counter-clockwise edge: outside
  }
  return true;
}

}  // namespace

OutlierTrim trimOutliers(const std::vector<Eigen::Vector3d>& points, DbscanResult& result,
                         const std::vector<Eigen::Vector3d>& support, const OutlierTrimParams& params) {
  if (!(std::isfinite(params.radius) && params.radius > 0.0))
    throw Error::inParameter("radius", "must be finite and > 0");
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
    return Cell{static_cast<std::int64_t>(std::floor(p.x() / side)),
                static_cast<std::int64_t>(std::floor(p.y() / side)),
                static_cast<std::int64_t>(std::floor(p.z() / side))};
  };
  std::unordered_map<Cell, std::vector<std::size_t>, CellHash> grid;
  for (std::size_t k = 0; k < n + support.size(); ++k) grid[keyOf(at(k))].push_back(k);

  const double radius2 = params.radius * params.radius;
  const double reach2 = params.reach * params.reach;
  // The candidates alone within radius: they support nothing (two outliers do not hold each other up).
  const auto forNear = [&](const Eigen::Vector3d& p, auto&& f) {
    const Cell c = keyOf(p);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto cell = grid.find(Cell{c.x + dx, c.y + dy, c.z + dz});
          if (cell == grid.end()) continue;
          for (const std::size_t k : cell->second)
            if (!f(k)) return;
        }
  };
  std::vector<char> alone(n, 0);
  std::vector<std::size_t> lone;
  for (const std::size_t i : candidates) {
    bool none = true;
    forNear(points[i], [&](std::size_t k) {
      none = k == i || (at(k) - points[i]).squaredNorm() > radius2;
      return none;
    });
    if (none) {
      alone[i] = 1;
      lone.push_back(i);
    }
  }
  std::vector<std::size_t> drop;
  std::vector<std::size_t> near;  // supporting points within reach of the candidate
  std::vector<Eigen::Vector3d> patch;
  for (const std::size_t i : lone) {
    const Eigen::Vector3d& p = points[i];
    near.clear();
    forNear(p, [&](std::size_t k) {
      if ((k >= n || (result.labels[k] >= 0 && !alone[k])) && (at(k) - p).squaredNorm() <= reach2) near.push_back(k);
      return true;
    });
    // In the order of the indices, so that the answer does not depend on the grid's layout.
    std::sort(near.begin(), near.end());
    patch.clear();
    for (const std::size_t k : near) patch.push_back(at(k));
    if (offAFlatPatch(p, patch, params.radius)) drop.push_back(i);
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
