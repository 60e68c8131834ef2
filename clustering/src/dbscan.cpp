#include "hullmap/clustering/dbscan.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <limits>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include "hullmap/mapper/error.hpp"

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
  throw Error("--metric: expected xyz or xy, got '" + text + "'");
}

std::string toString(Metric metric) { return metric == Metric::kXy ? "xy" : "xyz"; }

namespace detail {
namespace {

using Index = std::uint32_t;
constexpr Index kNone = std::numeric_limits<Index>::max();

struct CellCoord {
  std::int64_t x = 0, y = 0, z = 0;
  bool operator==(const CellCoord& o) const { return x == o.x && y == o.y && z == o.z; }
  bool operator<(const CellCoord& o) const {
    if (x != o.x) return x < o.x;
    if (y != o.y) return y < o.y;
    return z < o.z;
  }
};

/// Bounding box of a cell's points, in float rounded outwards: conservative for pruning.
struct CellBox {
  std::array<float, 3> lo;
  std::array<float, 3> hi;
};

inline std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

inline std::uint64_t hashCoord(const CellCoord& c) {
  return mix64(static_cast<std::uint64_t>(c.x) * 0x9E3779B97F4A7C15ULL ^
               mix64(static_cast<std::uint64_t>(c.y) + 0x632BE59BD9B4E019ULL) ^
               mix64(static_cast<std::uint64_t>(c.z) * 0x85EBCA77C2B2AE63ULL + 1));
}

/// Interleaves the low 4 bits of x, y, z (Morton order inside a 16^3 block).
inline std::uint64_t morton4(std::uint64_t x, std::uint64_t y, std::uint64_t z) {
  std::uint64_t m = 0;
  for (int b = 0; b < 4; ++b) {
    m |= ((x >> b) & 1) << (3 * b + 2) | ((y >> b) & 1) << (3 * b + 1) | ((z >> b) & 1) << (3 * b);
  }
  return m;
}

/// Sort key: a hash of the 16^3-cell block in the high 52 bits, the Morton code of the cell inside the
/// block in the low 12. Cells of one block end up next to each other (locality) whatever the extent of
/// the cloud. Two cells may share a key (hash collision); the caller separates them.
inline std::uint64_t sortKey(const CellCoord& c) {
  const CellCoord block{c.x >> 4, c.y >> 4, c.z >> 4};
  return (hashCoord(block) & ~std::uint64_t{0xFFF}) |
         morton4(static_cast<std::uint64_t>(c.x) & 15, static_cast<std::uint64_t>(c.y) & 15,
                 static_cast<std::uint64_t>(c.z) & 15);
}

template <int D>
inline double squaredDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double dx = a.x() - b.x();
  const double dy = a.y() - b.y();
  if constexpr (D == 3) {
    const double dz = a.z() - b.z();
    return dx * dx + dy * dy + dz * dz;
  } else {
    return dx * dx + dy * dy;
  }
}

/// Smallest squared distance from p to the box (0 inside).
template <int D>
inline double minSquaredDistance(const Eigen::Vector3d& p, const CellBox& b) {
  double s = 0.0;
  for (int k = 0; k < D; ++k) {
    const double v = p[k];
    const double d = v < b.lo[k] ? b.lo[k] - v : (v > b.hi[k] ? v - b.hi[k] : 0.0);
    s += d * d;
  }
  return s;
}

/// Largest squared distance from p to any point of the box.
template <int D>
inline double maxSquaredDistance(const Eigen::Vector3d& p, const CellBox& b) {
  double s = 0.0;
  for (int k = 0; k < D; ++k) {
    const double d = std::max(std::abs(p[k] - b.lo[k]), std::abs(b.hi[k] - p[k]));
    s += d * d;
  }
  return s;
}

template <int D>
inline double minSquaredDistance(const CellBox& a, const CellBox& b) {
  double s = 0.0;
  for (int k = 0; k < D; ++k) {
    const double d = a.hi[k] < b.lo[k] ? double(b.lo[k]) - a.hi[k] : (b.hi[k] < a.lo[k] ? double(a.lo[k]) - b.hi[k] : 0.0);
    s += d * d;
  }
  return s;
}

template <int D>
inline double maxSquaredDistance(const CellBox& a, const CellBox& b) {
  double s = 0.0;
  for (int k = 0; k < D; ++k) {
    const double d = std::max(double(a.hi[k]) - b.lo[k], double(b.hi[k]) - a.lo[k]);
    s += d * d;
  }
  return s;
}

/// Open-addressing hash table from cell coordinates to cell index (the coordinates live in `coords`).
class CellTable {
 public:
  explicit CellTable(const std::vector<CellCoord>& coords) : coords_(coords) {
    std::size_t size = 16;
    while (size < 2 * coords.size()) size *= 2;
    mask_ = size - 1;
    slots_.assign(size, kNone);
    for (Index c = 0; c < coords.size(); ++c) {
      std::size_t s = hashCoord(coords[c]) & mask_;
      while (slots_[s] != kNone) s = (s + 1) & mask_;
      slots_[s] = c;
    }
  }

  Index find(const CellCoord& c) const {
    std::size_t s = hashCoord(c) & mask_;
    while (true) {
      const Index v = slots_[s];
      if (v == kNone || coords_[v] == c) return v;
      s = (s + 1) & mask_;
    }
  }

 private:
  const std::vector<CellCoord>& coords_;
  std::vector<Index> slots_;
  std::size_t mask_ = 0;
};

/// Lock-free union-find over cells; a root is always linked under the smaller root.
class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(new std::atomic<Index>[n]) {
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) { parent_[i].store(Index(i), std::memory_order_relaxed); });
  }

  Index find(Index x) const {
    while (true) {
      Index p = parent_[x].load(std::memory_order_relaxed);
      if (p == x) return x;
      const Index gp = parent_[p].load(std::memory_order_relaxed);
      if (gp != p) parent_[x].compare_exchange_weak(p, gp, std::memory_order_relaxed);
      x = gp;
    }
  }

  void unite(Index a, Index b) {
    while (true) {
      a = find(a);
      b = find(b);
      if (a == b) return;
      if (a < b) std::swap(a, b);
      Index expected = a;
      if (parent_[a].compare_exchange_strong(expected, b, std::memory_order_relaxed)) return;
    }
  }

 private:
  std::unique_ptr<std::atomic<Index>[]> parent_;
};

template <int D>
class GridDbscan {
 public:
  GridDbscan(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
             const DbscanParams& params)
      : input_(points), input_weights_(weights), params_(params), eps2_(params.eps * params.eps) {
    // A hair below eps/sqrt(d), so that rounding in the cell assignment and in the distance of two
    // points of one cell can never make a cell wider than eps.
    side_ = params.eps / std::sqrt(double(D)) * (1.0 - 1e-6);
    inv_side_ = 1.0 / side_;
    for (int dx = -2; dx <= 2; ++dx)
      for (int dy = -2; dy <= 2; ++dy)
        for (int dz = (D == 3 ? -2 : 0); dz <= (D == 3 ? 2 : 0); ++dz)
          if (dx != 0 || dy != 0 || dz != 0) stencil_.push_back({dx, dy, dz});
    // Nearest cells first: counting and border searches stop earlier.
    std::stable_sort(stencil_.begin(), stencil_.end(), [](const CellCoord& a, const CellCoord& b) {
      return a.x * a.x + a.y * a.y + a.z * a.z < b.x * b.x + b.y * b.y + b.z * b.z;
    });
  }

  DbscanResult run() {
    buildGrid();
    markCore();
    joinCoreCells();
    return label();
  }

 private:
  CellCoord cellOf(const Eigen::Vector3d& p) const {
    const auto f = [&](double v) { return static_cast<std::int64_t>(std::floor(v * inv_side_)); };
    return CellCoord{f(p.x()), f(p.y()), D == 3 ? f(p.z()) : 0};
  }

  std::uint64_t weightOf(Index sorted) const { return input_weights_.empty() ? 1 : input_weights_[order_[sorted]]; }

  void buildGrid() {
    const std::size_t n = input_.size();
    constexpr double kLimit = 4.0e18;  // |cell coordinate| must fit in int64 with room for the stencil
    std::vector<std::pair<std::uint64_t, Index>> keyed(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const Eigen::Vector3d& p = input_[i];
        for (int k = 0; k < D; ++k) {
          if (!(std::abs(p[k] * inv_side_) < kLimit)) {
            throw Error("dbscan: point " + std::to_string(i) +
                        (std::isfinite(p[k]) ? " is too far from the origin for eps" : " is not finite"));
          }
        }
        keyed[i] = {sortKey(cellOf(p)), Index(i)};
      }
    });
    tbb::parallel_sort(keyed.begin(), keyed.end());

    // Separate cells that share a key (hash collisions of their blocks): sort such runs by coordinates.
    for (std::size_t a = 0; a < n;) {
      std::size_t b = a + 1;
      while (b < n && keyed[b].first == keyed[a].first) ++b;
      const CellCoord first = cellOf(input_[keyed[a].second]);
      bool mixed = false;
      for (std::size_t j = a + 1; j < b && !mixed; ++j) mixed = !(cellOf(input_[keyed[j].second]) == first);
      if (mixed) {
        std::sort(keyed.begin() + a, keyed.begin() + b, [&](const auto& u, const auto& v) {
          const CellCoord cu = cellOf(input_[u.second]);
          const CellCoord cv = cellOf(input_[v.second]);
          if (!(cu == cv)) return cu < cv;
          return u.second < v.second;
        });
      }
      a = b;
    }

    order_.resize(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t j) { order_[j] = keyed[j].second; });
    std::vector<std::pair<std::uint64_t, Index>>().swap(keyed);

    pts_.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t j = r.begin(); j != r.end(); ++j) pts_[j] = input_[order_[j]];
    });

    CellCoord previous{};
    for (std::size_t j = 0; j < n; ++j) {
      const CellCoord c = cellOf(pts_[j]);
      if (j == 0 || !(c == previous)) {
        start_.push_back(Index(j));
        coords_.push_back(c);
        previous = c;
      }
    }
    start_.push_back(Index(n));
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
        for (int k = 0; k < 3; ++k) {
          b.lo[k] = std::nextafter(static_cast<float>(lo[k]), -std::numeric_limits<float>::infinity());
          b.hi[k] = std::nextafter(static_cast<float>(hi[k]), std::numeric_limits<float>::infinity());
        }
        cell_weight_[c] = w;
      }
    });
    table_ = std::make_unique<CellTable>(coords_);
  }

  /// Existing cells of the stencil around `c`, nearest offsets first.
  int neighbours(Index c, std::array<Index, 124>& out) const {
    int count = 0;
    const CellCoord& base = coords_[c];
    for (const CellCoord& o : stencil_) {
      const Index other = table_->find(CellCoord{base.x + o.x, base.y + o.y, base.z + o.z});
      if (other != kNone) out[count++] = other;
    }
    return count;
  }

  void markCore() {
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

  /// True when some core point of a is within eps of some core point of b (early exit).
  bool coreLinked(Index a, Index b) const {
    if (cell_core_[a] == kAllCore && cell_core_[b] == kAllCore &&
        maxSquaredDistance<D>(boxes_[a], boxes_[b]) <= eps2_) {
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

  void joinCoreCells() {
    const std::size_t cells = coords_.size();
    sets_ = std::make_unique<UnionFind>(cells);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 64), [&](const tbb::blocked_range<std::size_t>& r) {
      std::array<Index, 124> near;
      for (std::size_t c = r.begin(); c != r.end(); ++c) {
        if (cell_core_[c] == kNoCore) continue;
        const int m = neighbours(Index(c), near);
        for (int t = 0; t < m; ++t) {
          const Index o = near[t];
          if (o < c || cell_core_[o] == kNoCore) continue;  // each pair once
          if (minSquaredDistance<D>(boxes_[c], boxes_[o]) > eps2_) continue;
          if (sets_->find(Index(c)) == sets_->find(o)) continue;
          if (coreLinked(Index(c), o)) sets_->unite(Index(c), o);
        }
      }
    });
  }

  /// Nearest core neighbour of the non-core point j of cell c (ties: first in the input), or kNone.
  Index nearestCore(Index j, Index c, const std::array<Index, 124>& near, int m) const {
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

  DbscanResult label() {
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

  /// The cell holding sorted position q, known to be c or one of its neighbours.
  Index cellOfSorted(Index q, Index c, const std::array<Index, 124>& near, int m) const {
    if (q >= start_[c] && q < start_[c + 1]) return c;
    for (int t = 0; t < m; ++t) {
      if (q >= start_[near[t]] && q < start_[near[t] + 1]) return near[t];
    }
    assert(false);
    return c;
  }

  static constexpr std::uint8_t kNoCore = 0, kSomeCore = 1, kAllCore = 2;

  const std::vector<Eigen::Vector3d>& input_;
  const std::vector<std::uint32_t>& input_weights_;
  DbscanParams params_;
  double eps2_;
  double side_ = 0.0;
  double inv_side_ = 0.0;
  std::vector<CellCoord> stencil_;

  std::vector<Eigen::Vector3d> pts_;       // points sorted by cell
  std::vector<Index> order_;               // sorted position -> input index
  std::vector<Index> start_;               // cell -> first sorted position; size cells + 1
  std::vector<CellCoord> coords_;          // cell -> grid coordinates
  std::vector<CellBox> boxes_;             // cell -> bounding box of its points
  std::vector<std::uint64_t> cell_weight_; // cell -> summed weight
  std::unique_ptr<CellTable> table_;
  std::vector<std::uint8_t> core_;         // sorted position -> core
  std::vector<std::uint8_t> cell_core_;    // cell -> kNoCore, kSomeCore, kAllCore
  std::unique_ptr<UnionFind> sets_;
};

}  // namespace
}  // namespace detail

DbscanResult dbscan(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
                    const DbscanParams& params) {
  if (!(params.eps > 0.0) || !std::isfinite(params.eps)) {
    throw Error("dbscan: eps must be a positive finite number, got " + std::to_string(params.eps));
  }
  if (params.min_pts < 1) throw Error("dbscan: min_pts must be >= 1, got " + std::to_string(params.min_pts));
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
  if (params.metric == Metric::kXy) return detail::GridDbscan<2>(points, weights, params).run();
  return detail::GridDbscan<3>(points, weights, params).run();
}

}  // namespace hullmap::clustering
