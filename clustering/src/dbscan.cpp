// Exact DBSCAN on a grid (GridDbscan, grid_dbscan.hpp): cells just under eps / sqrt(d), Morton-sorted
// points, cell-to-cell distance bounds, the core pass, a concurrent union-find and the border pass.
#include "hullmap/clustering/dbscan.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "grid_dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "key_sort.hpp"

// Grid DBSCAN after Gunawan (2013), Wang, Gu and Shun (SIGMOD 2020) and ArborX's FDBSCAN-DenseBox:
//  1. points are binned into cells of side slightly below eps/sqrt(d), so any two points of a cell are
//     neighbours; cells are found by sorting points on a 64-bit cell key, then looked up in a hash
//     table from cell coordinates to cell index (never a dense array: gross outliers are fine);
//  2. a cell of weight >= min_pts makes all its points core; other points count neighbours in the
//     5^d stencil and stop at min_pts;
//  3. core cells are joined by a lock-free union-find when some pair of their core points is
//     within eps (early exit on the first pair, bounding boxes prune);
//  4. non-core points take the cluster of their nearest core neighbour.
// Memory: the sorted copy of the points, a permutation, per-point flags and per-cell arrays.

namespace hullmap::clustering {

Metric parseMetric(const std::string& text) {
  if (text == "xyz") return Metric::kXyz;
  if (text == "xy") return Metric::kXy;
  throw Error::inParameter("metric", "expected xyz or xy, got '" + text + "'");
}

std::string toString(Metric metric) { return metric == Metric::kXy ? "xy" : "xyz"; }

namespace detail {

template <int D>
void GridDbscan<D>::buildGrid() {
  const std::size_t n = input_.size();
  constexpr double kLimit = 4.0e18;  // |cell coordinate| must fit in int64 with room for the stencil
  BigVector<KeyedPoint> keyed(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const Eigen::Vector3d& p = input_[i];
      for (int k = 0; k < D; ++k) {
        if (!(std::abs(p[k] * inv_side_) < kLimit)) {
          throw Error("dbscan: point " + std::to_string(i) +
                      (std::isfinite(p[k]) ? " is too far from the origin for eps" : " is not finite"));
        }
      }
      keyed[i] = KeyedPoint{sortKey(cellOf(p)), Index(i)};
    }
  });
  sortByKey(keyed);

  // Cells start where the key changes. The keys go before the sorted points arrive, to keep the
  // peak memory low.
  order_.resize(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t j) { order_[j] = keyed[j].index; });
  BigVector<Index> run_start;
  for (std::size_t j = 0; j < n; ++j) {
    if (j == 0 || keyed[j].key != keyed[j - 1].key) run_start.push_back(Index(j));
  }
  run_start.push_back(Index(n));
  BigVector<KeyedPoint>().swap(keyed);

  pts_.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t j = r.begin(); j != r.end(); ++j) pts_[j] = input_[order_[j]];
  });

  // Two cells may share a key (a hash collision of their blocks): such a run is sorted by
  // coordinates and split where the coordinates change.
  const std::size_t runs = run_start.size() - 1;
  coords_.resize(runs);
  const bool collision = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, runs, 256), false,
      [&](const tbb::blocked_range<std::size_t>& r, bool mixed) {
        for (std::size_t c = r.begin(); c != r.end(); ++c) {
          coords_[c] = cellOf(pts_[run_start[c]]);
          for (Index j = run_start[c] + 1; j < run_start[c + 1] && !mixed; ++j)
            mixed = !(cellOf(pts_[j]) == coords_[c]);
        }
        return mixed;
      },
      [](bool x, bool y) { return x || y; });
  if (!collision) {
    start_.swap(run_start);
  } else {
    coords_.clear();
    for (std::size_t c = 0; c < runs; ++c) {
      const std::size_t a = run_start[c], b = run_start[c + 1];
      std::sort(order_.begin() + a, order_.begin() + b, [&](Index u, Index v) {
        const CellCoord cu = cellOf(input_[u]);
        const CellCoord cv = cellOf(input_[v]);
        if (!(cu == cv)) return cu < cv;
        return u < v;
      });
      for (std::size_t j = a; j < b; ++j) {
        pts_[j] = input_[order_[j]];
        const CellCoord cell = cellOf(pts_[j]);
        if (j == a || !(cell == coords_.back())) {
          start_.push_back(Index(j));
          coords_.push_back(cell);
        }
      }
    }
    start_.push_back(Index(n));
  }
  const std::size_t cells = coords_.size();

  boxes_.resize(cells);
  cell_weight_.resize(cells);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 256), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t c = r.begin(); c != r.end(); ++c) {
      Eigen::Vector3d lo = pts_[start_[c]], hi = pts_[start_[c]];
      std::uint64_t w = 0;
      for (Index j = start_[c]; j < start_[c + 1]; ++j) {
        lo = lo.cwiseMin(pts_[j]);
        hi = hi.cwiseMax(pts_[j]);
        w += weightOf(j);
      }
      CellBox& b = boxes_[c];
      // Float bounds that still contain every point; then every distance to a point of the box is
      // at most the box's computed maximum (rounding is monotone), which makes the whole-box tests exact.
      for (int k = 0; k < 3; ++k) {
        b.lo[k] = static_cast<float>(lo[k]);
        if (double(b.lo[k]) > lo[k]) b.lo[k] = std::nextafter(b.lo[k], -std::numeric_limits<float>::infinity());
        b.hi[k] = static_cast<float>(hi[k]);
        if (double(b.hi[k]) < hi[k]) b.hi[k] = std::nextafter(b.hi[k], std::numeric_limits<float>::infinity());
      }
      cell_weight_[c] = w;
    }
  });
  table_ = std::make_unique<CellTable>(coords_);
}

template <int D>
int GridDbscan<D>::neighbours(Index c, std::array<Index, 124>& out, bool forward_only) const {
  const CellCoord& base = coords_[c];
  const CellBox& box = boxes_[c];
  // gap2[k][o + 2]: squared gap along axis k between the box and the cell at offset o. The slack
  // covers rounding in the cell assignment, so a gap is never overestimated.
  double gap2[3][5] = {};
  for (int k = 0; k < D; ++k) {
    const double slack = side_ * 1e-6 + 1e-14 * std::max(std::abs(double(box.lo[k])), std::abs(double(box.hi[k])));
    for (int o = -2; o <= 2; ++o) {
      double g = 0.0;
      if (o > 0) g = double(base[k] + o) * side_ - box.hi[k];
      if (o < 0) g = box.lo[k] - double(base[k] + o + 1) * side_;
      g = std::max(0.0, g - slack);
      gap2[k][o + 2] = g * g;
    }
  }
  // Nested loops, nearest offsets first on each axis, so that whole rows and planes of the stencil
  // are skipped at once (sparse clouds spend most of their time here).
  static constexpr int kOrder[5] = {0, -1, 1, -2, 2};
  int count = 0;
  for (int dx : kOrder) {
    const double gx = gap2[0][dx + 2];
    if (gx > eps2_) continue;
    for (int dy : kOrder) {
      const double gxy = gx + gap2[1][dy + 2];
      if (gxy > eps2_) continue;
      for (int dz : kOrder) {
        if (D == 2 && dz != 0) continue;
        if (gxy + gap2[2][dz + 2] > eps2_) continue;
        if (dx == 0 && dy == 0 && dz == 0) continue;
        if (forward_only && !(dx > 0 || (dx == 0 && (dy > 0 || (dy == 0 && dz > 0))))) continue;
        const Index other = table_->find(CellCoord{base.x + dx, base.y + dy, base.z + dz});
        if (other != kNone) out[count++] = other;
      }
    }
  }
  return count;
}

template <int D>
void GridDbscan<D>::markCore() {
  const std::size_t cells = coords_.size();
  const std::uint64_t min_pts = std::uint64_t(params_.min_pts);
  core_.assign(pts_.size(), 0);
  cell_core_.assign(cells, kNoCore);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 64), [&](const tbb::blocked_range<std::size_t>& r) {
    std::array<Index, 124> near;
    for (std::size_t c = r.begin(); c != r.end(); ++c) {
      if (cell_weight_[c] >= min_pts) {
        std::fill(core_.begin() + start_[c], core_.begin() + start_[c + 1], 1);
        cell_core_[c] = kAllCore;
        continue;
      }
      const int m = neighbours(Index(c), near);
      int cores = 0;
      for (Index j = start_[c]; j < start_[c + 1]; ++j) {
        const Eigen::Vector3d& p = pts_[j];
        std::uint64_t count = cell_weight_[c];
        for (int t = 0; t < m && count < min_pts; ++t) {
          const Index o = near[t];
          const CellBox& box = boxes_[o];
          if (minSquaredDistance<D>(p, box) > eps2_) continue;
          if (maxSquaredDistance<D>(p, box) <= eps2_) {
            count += cell_weight_[o];
            continue;
          }
          for (Index q = start_[o]; q < start_[o + 1] && count < min_pts; ++q) {
            if (squaredDistance<D>(p, pts_[q]) <= eps2_) count += weightOf(q);
          }
        }
        if (count >= min_pts) {
          core_[j] = 1;
          ++cores;
        }
      }
      if (cores > 0) cell_core_[c] = cores == int(start_[c + 1] - start_[c]) ? kAllCore : kSomeCore;
    }
  });
}

template <int D>
bool GridDbscan<D>::coreLinked(Index a, Index b) const {
  if (cell_core_[a] == kAllCore && cell_core_[b] == kAllCore && maxSquaredDistance<D>(boxes_[a], boxes_[b]) <= eps2_) {
    return true;
  }
  // Iterate the smaller cell on the outside.
  if (start_[a + 1] - start_[a] > start_[b + 1] - start_[b]) std::swap(a, b);
  const CellBox& box_b = boxes_[b];
  for (Index i = start_[a]; i < start_[a + 1]; ++i) {
    if (!core_[i]) continue;
    const Eigen::Vector3d& p = pts_[i];
    if (minSquaredDistance<D>(p, box_b) > eps2_) continue;
    for (Index j = start_[b]; j < start_[b + 1]; ++j) {
      if (core_[j] && squaredDistance<D>(p, pts_[j]) <= eps2_) return true;
    }
  }
  return false;
}

template <int D>
void GridDbscan<D>::joinCoreCells() {
  const std::size_t cells = coords_.size();
  sets_ = std::make_unique<UnionFind>(cells);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 64), [&](const tbb::blocked_range<std::size_t>& r) {
    std::array<Index, 124> near;
    for (std::size_t c = r.begin(); c != r.end(); ++c) {
      if (cell_core_[c] == kNoCore) continue;
      const int m = neighbours(Index(c), near, true);  // each pair of cells once
      for (int t = 0; t < m; ++t) {
        const Index o = near[t];
        if (cell_core_[o] == kNoCore) continue;
        if (minSquaredDistance<D>(boxes_[c], boxes_[o]) > eps2_) continue;
        if (sets_->find(Index(c)) == sets_->find(o)) continue;
        if (coreLinked(Index(c), o)) sets_->unite(Index(c), o);
      }
    }
  });
}

template <int D>
Index GridDbscan<D>::nearestCore(Index j, Index c, const std::array<Index, 124>& near, int m) const {
  const Eigen::Vector3d& p = pts_[j];
  double best = eps2_;
  Index best_q = kNone;
  const auto scan = [&](Index o) {
    if (cell_core_[o] == kNoCore || minSquaredDistance<D>(p, boxes_[o]) > best) return;
    for (Index q = start_[o]; q < start_[o + 1]; ++q) {
      if (!core_[q]) continue;
      const double d = squaredDistance<D>(p, pts_[q]);
      if (d < best || (d == best && (best_q == kNone || order_[q] < order_[best_q]))) {
        best = d;
        best_q = q;
      }
    }
  };
  scan(c);
  for (int t = 0; t < m; ++t) scan(near[t]);
  return best_q;
}

template <int D>
DbscanResult GridDbscan<D>::label() {
  const std::size_t n = pts_.size();
  const std::size_t cells = coords_.size();
  DbscanResult result;
  result.labels.assign(n, kNoise);
  result.core.assign(n, 0);
  // First the root cell of each point's cluster (or kNoise), in input order.
  std::vector<std::int32_t>& root = result.labels;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 64), [&](const tbb::blocked_range<std::size_t>& r) {
    std::array<Index, 124> near;
    for (std::size_t c = r.begin(); c != r.end(); ++c) {
      if (cell_core_[c] == kAllCore) {
        const auto cluster = std::int32_t(sets_->find(Index(c)));
        for (Index j = start_[c]; j < start_[c + 1]; ++j) {
          root[order_[j]] = cluster;
          result.core[order_[j]] = 1;
        }
        continue;
      }
      int m = -1;
      for (Index j = start_[c]; j < start_[c + 1]; ++j) {
        if (core_[j]) {
          root[order_[j]] = std::int32_t(sets_->find(Index(c)));
          result.core[order_[j]] = 1;
          continue;
        }
        if (m < 0) m = neighbours(Index(c), near);
        const Index q = nearestCore(j, Index(c), near, m);
        if (q != kNone) root[order_[j]] = std::int32_t(sets_->find(cellOfSorted(q, Index(c), near, m)));
      }
    }
  });
  // Number the clusters by their first point in the input.
  std::vector<std::int32_t> number(cells, kNoise);
  std::int32_t next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t r = root[i];
    if (r == kNoise) {
      ++result.noise;
      continue;
    }
    if (number[r] == kNoise) {
      number[r] = next++;
      result.cluster_sizes.push_back(0);
    }
    root[i] = number[r];
    ++result.cluster_sizes[number[r]];
  }
  return result;
}

template <int D>
Index GridDbscan<D>::cellOfSorted(Index q, Index c, const std::array<Index, 124>& near, int m) const {
  if (q >= start_[c] && q < start_[c + 1]) return c;
  for (int t = 0; t < m; ++t) {
    if (q >= start_[near[t]] && q < start_[near[t] + 1]) return near[t];
  }
  assert(false);
  return c;
}

}  // namespace detail

namespace {

DbscanResult runDbscan(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
                       const DbscanParams& params, const KDistanceRequest* k_distance) {
  if (!(params.eps > 0.0) || !std::isfinite(params.eps)) {
    throw Error::inParameter("eps", "must be a positive finite number, got " + std::to_string(params.eps));
  }
  if (params.min_pts < 1) throw Error::inParameter("min_pts", "must be >= 1, got " + std::to_string(params.min_pts));
  if (!weights.empty() && weights.size() != points.size()) {
    throw Error("dbscan: " + std::to_string(weights.size()) + " weights for " + std::to_string(points.size()) +
                " points");
  }
  if (points.size() >= std::size_t(detail::kNone) - 1) {
    throw Error("dbscan: too many points (" + std::to_string(points.size()) + ")");
  }
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (weights[i] == 0) throw Error("dbscan: weight of point " + std::to_string(i) + " is 0");
  }
  if (points.empty()) return DbscanResult{};
  if (params.metric == Metric::kXy) return detail::GridDbscan<2>(points, weights, params).run(k_distance);
  return detail::GridDbscan<3>(points, weights, params).run(k_distance);
}

}  // namespace

DbscanResult dbscan(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
                    const DbscanParams& params) {
  return runDbscan(points, weights, params, nullptr);
}

DbscanResult dbscan(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
                    const DbscanParams& params, const KDistanceRequest& k_distance) {
  return runDbscan(points, weights, params, &k_distance);
}

}  // namespace hullmap::clustering
