#include "hullmap/clustering/cluster_extension.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "hullmap/core/error.hpp"
#include "hullmap/core/lattice.hpp"
#include "hullmap/core/number_text.hpp"

namespace hullmap::clustering {
namespace {

using core::Cell;
using core::CellHash;

/// Cell -> index, open addressing with linear probing (a lookup is about one cache miss: the
/// extension looks up 27 cells for each noise point, most of them empty).
class CellTable {
 public:
  explicit CellTable(std::size_t expected) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected) capacity *= 2;
    slots_.resize(capacity);
    mask_ = capacity - 1;
  }
  /// The index of `c`, inserting `next` for it when absent; second: whether it was inserted.
  std::pair<std::uint32_t, bool> insert(const Cell& c, std::uint32_t next) {
    for (std::size_t i = CellHash{}(c)&mask_;; i = (i + 1) & mask_) {
      Slot& s = slots_[i];
      if (s.index == kEmpty) {
        s = {c, next};
        return {next, true};
      }
      if (s.cell == c) return {s.index, false};
    }
  }
  /// The index of `c`, or kEmpty.
  std::uint32_t find(const Cell& c) const {
    for (std::size_t i = CellHash{}(c)&mask_;; i = (i + 1) & mask_) {
      const Slot& s = slots_[i];
      if (s.index == kEmpty || s.cell == c) return s.index;
    }
  }
  static constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();

 private:
  struct Slot {
    Cell cell;
    std::uint32_t index = kEmpty;
  };
  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
};

std::string number(double v) {
  char text[core::kShortestTextMax];
  return std::string(text, core::writeShortest(text, v));
}

void checkExtensionInput(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
                         const DbscanResult& result, const ClusterExtensionParams& params) {
  if (!(std::isfinite(params.eps) && params.eps > 0.0)) throw Error::inParameter("eps", "must be finite and > 0");
  if (params.min_pts < 1) throw Error::inParameter("min_pts", "must be >= 1, got " + std::to_string(params.min_pts));
  if (!(std::isfinite(params.reach) && params.reach >= params.eps))
    throw Error::inParameter("reach",
                             "must be finite and >= eps (" + number(params.eps) + "), got " + number(params.reach));
  const std::size_t n = points.size();
  if (!weights.empty() && weights.size() != n)
    throw Error::inParameter("weights",
                             std::to_string(weights.size()) + " weights for " + std::to_string(n) + " points");
  if (result.labels.size() != n)
    throw Error::inParameter("labels",
                             std::to_string(result.labels.size()) + " labels for " + std::to_string(n) + " points");
  const auto clusters = static_cast<std::int64_t>(result.cluster_sizes.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (!points[i].allFinite()) throw Error::inParameter("points", "point " + std::to_string(i) + " is not finite");
    if (!weights.empty() && weights[i] == 0)
      throw Error::inParameter("weights", "point " + std::to_string(i) + " has weight 0");
    if (result.labels[i] < kNoise || result.labels[i] >= clusters)
      throw Error::inParameter("labels", "point " + std::to_string(i) + " has label " +
                                             std::to_string(result.labels[i]) + ", not kNoise or a cluster below " +
                                             std::to_string(clusters));
  }
}

/// The points by cell, cells of side slightly above reach (>= eps): every point within reach of p
/// lies in the 27 (9 under kXy) cells around p's, rounding included. Cells beyond +-2^50 are clamped
/// there: a clamped cell only holds points as far out as its own, and the distances stay exact.
class ReachGrid {
 public:
  ReachGrid(const std::vector<Eigen::Vector3d>& points, double reach, bool xy)
      : points_(points), side_(reach * (1.0 + 1e-9)), xy_(xy), cell_index_(points.size()) {
    // The grid: cell -> its range in `members_` (points by cell, in input order within a cell).
    const std::size_t n = points.size();
    std::vector<std::uint32_t> point_cell(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto [index, added] = cell_index_.insert(cellOf(i), static_cast<std::uint32_t>(cell_begin_.size()));
      if (added) cell_begin_.push_back(0);
      point_cell[i] = index;
      ++cell_begin_[index];
    }
    std::uint32_t total = 0;
    for (auto& b : cell_begin_) total += std::exchange(b, total);
    cell_begin_.push_back(total);
    members_.resize(n);
    std::vector<std::uint32_t> fill(cell_begin_.begin(), cell_begin_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) members_[fill[point_cell[i]]++] = static_cast<std::uint32_t>(i);
  }

  /// Calls f(q, squared distance) for the points q in the cells around p until f returns false.
  template <class F>
  void forEachNear(std::size_t p, F&& f) const {
    const Cell c = cellOf(p);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = xy_ ? 0 : -1; dz <= (xy_ ? 0 : 1); ++dz) {
          const std::uint32_t cell = cell_index_.find(Cell{c.x + dx, c.y + dy, c.z + dz});
          if (cell == CellTable::kEmpty) continue;
          for (std::uint32_t k = cell_begin_[cell], end = cell_begin_[cell + 1]; k < end; ++k)
            if (!f(members_[k], squaredDistance(p, members_[k]))) return;
        }
  }

 private:
  double squaredDistance(std::size_t a, std::size_t b) const {
    const double dx = points_[a].x() - points_[b].x();
    const double dy = points_[a].y() - points_[b].y();
    if (xy_) return dx * dx + dy * dy;
    const double dz = points_[a].z() - points_[b].z();
    return dx * dx + dy * dy + dz * dz;
  }
  Cell cellOf(std::size_t i) const {
    constexpr double kClamp = 1125899906842624.0;  // 2^50
    auto c = [&](double v) { return static_cast<std::int64_t>(std::clamp(std::floor(v / side_), -kClamp, kClamp)); };
    return Cell{c(points_[i].x()), c(points_[i].y()), xy_ ? 0 : c(points_[i].z())};
  }

  const std::vector<Eigen::Vector3d>& points_;
  double side_;
  bool xy_;
  CellTable cell_index_;
  std::vector<std::uint32_t> cell_begin_, members_;
};

}  // namespace

ClusterExtension extendClusters(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
                                DbscanResult& result, const ClusterExtensionParams& params) {
  checkExtensionInput(points, weights, result, params);
  const std::size_t n = points.size();
  ClusterExtension out;
  if (n == 0 || result.cluster_sizes.empty()) return out;
  const ReachGrid grid(points, params.reach, params.metric == Metric::kXy);
  const auto forEachNear = [&grid](std::size_t p, auto&& f) { grid.forEachNear(p, f); };

  const double eps2 = params.eps * params.eps;
  const double reach2 = params.reach * params.reach;
  const auto min_weight = static_cast<double>(params.min_pts);
  auto isDense = [&](std::size_t p) {
    double weight = 0.0;
    forEachNear(p, [&](std::uint32_t q, double d2) {
      if (d2 <= eps2) weight += weights.empty() ? 1.0 : static_cast<double>(weights[q]);
      return weight < min_weight;
    });
    return weight >= min_weight;
  };
  // Density at the extension's level: every noise point's up front (in parallel), a clustered
  // point's when first asked (it only matters within reach of a dense noise point).
  enum : std::uint8_t { kUnknown, kSparse, kDense };
  std::vector<std::uint8_t> density(n, kUnknown);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t p = r.begin(); p < r.end(); ++p)
      if (result.labels[p] == kNoise) density[p] = isDense(p) ? kDense : kSparse;
  });
  auto dense = [&](std::size_t p) {
    if (density[p] == kUnknown) density[p] = isDense(p) ? kDense : kSparse;
    return density[p] == kDense;
  };

  std::vector<std::int32_t>& labels = result.labels;
  std::vector<std::uint32_t> candidates;
  for (std::size_t p = 0; p < n; ++p)
    if (labels[p] == kNoise && dense(p)) candidates.push_back(static_cast<std::uint32_t>(p));
  std::vector<std::pair<std::uint32_t, std::int32_t>> joins;
  std::vector<std::uint8_t> queued(n, 0);
  while (!candidates.empty()) {
    // Every candidate sees the labels of the rounds before this one only.
    joins.clear();
    for (std::uint32_t p : candidates) {
      double best = std::numeric_limits<double>::infinity();
      std::uint32_t best_index = std::numeric_limits<std::uint32_t>::max();
      forEachNear(p, [&](std::uint32_t q, double d2) {
        if (labels[q] == kNoise || d2 > reach2 || d2 > best || (d2 == best && q > best_index) || !dense(q)) return true;
        best = d2;
        best_index = q;
        return true;
      });
      if (best_index != std::numeric_limits<std::uint32_t>::max()) joins.emplace_back(p, labels[best_index]);
    }
    if (joins.empty()) break;
    ++out.rounds;
    for (const auto& [p, label] : joins) {
      labels[p] = label;
      ++result.cluster_sizes[static_cast<std::size_t>(label)];
    }
    out.joined += joins.size();
    // The next round's candidates: the dense noise points within reach of one that just joined
    // (no other point's nearest dense clustered point can have changed).
    candidates.clear();
    for (const auto& [p, label] : joins) {
      forEachNear(p, [&](std::uint32_t q, double d2) {
        if (labels[q] == kNoise && !queued[q] && d2 <= reach2 && dense(q)) {
          queued[q] = 1;
          candidates.push_back(q);
        }
        return true;
      });
    }
    for (std::uint32_t q : candidates) queued[q] = 0;
  }
  result.noise -= out.joined;
  return out;
}

ClusterExtensionParams extensionParams(const DbscanParams& used, const ClusterExtensionRule& rule) {
  if (!(std::isfinite(rule.min_pts_factor) && rule.min_pts_factor > 0.0 && rule.min_pts_factor <= 1.0))
    throw Error::inParameter("min_pts_factor", "must be in (0, 1], got " + number(rule.min_pts_factor));
  if (!(std::isfinite(rule.reach_factor) && rule.reach_factor >= 1.0))
    throw Error::inParameter("reach_factor", "must be finite and >= 1, got " + number(rule.reach_factor));
  if (rule.min_min_pts < 1)
    throw Error::inParameter("min_min_pts", "must be >= 1, got " + std::to_string(rule.min_min_pts));
  if (!(std::isfinite(used.eps) && used.eps > 0.0)) throw Error::inParameter("eps", "must be finite and > 0");
  ClusterExtensionParams p;
  p.eps = used.eps;
  p.min_pts = std::max(rule.min_min_pts, static_cast<int>(std::floor(rule.min_pts_factor * used.min_pts + 1e-9)));
  p.reach = rule.reach_factor * used.eps;
  p.metric = used.metric;
  return p;
}

}  // namespace hullmap::clustering
