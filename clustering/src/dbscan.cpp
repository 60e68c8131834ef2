// Exact DBSCAN on a grid (GridDbscan): cells just under eps / sqrt(d), Morton-sorted points, cell-to-cell
// distance bounds, the core pass, a concurrent union-find and the border pass. Over 600 lines as one
// job: the helpers above GridDbscan (cell boxes, the allocator, the union-find, the key sort) serve
// only it and share its layouts. Issue 26 may still move the union-find and the cell table to core/.
#include "hullmap/clustering/dbscan.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>

#include <stdlib.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "hullmap/core/error.hpp"
#include "hullmap/core/huge_pages.hpp"
#include "hullmap/core/lattice.hpp"

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
namespace {

using Index = std::uint32_t;
constexpr Index kNone = std::numeric_limits<Index>::max();

using CellCoord = core::Cell;

/// Bounding box of a cell's points, in float rounded outwards where float cannot hold the bound.
struct CellBox {
  std::array<float, 3> lo;
  std::array<float, 3> hi;
};

inline std::uint64_t hashCoord(const CellCoord& c) { return core::hashCell(c.x, c.y, c.z); }

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
    const double d =
        a.hi[k] < b.lo[k] ? double(b.lo[k]) - a.hi[k] : (b.hi[k] < a.lo[k] ? double(a.lo[k]) - b.hi[k] : 0.0);
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

/// Allocator for the engine's big arrays. Blocks of 2 MB and more are 2 MB aligned and asked to be
/// backed by transparent huge pages (core::adviseHugePages): first-touch page faults otherwise dominate the
/// run time on virtual machines (measured: 64 MB touched in 0.17 s with 4 kB pages, 0.006 s with
/// huge pages). construct() without arguments default-initialises, so resize() does not zero arrays
/// that are overwritten anyway.
template <typename T>
struct BigAllocator {
  using value_type = T;
  BigAllocator() = default;
  template <typename U>
  BigAllocator(const BigAllocator<U>&) {}

  T* allocate(std::size_t count) {
    const std::size_t bytes = count * sizeof(T);
    void* p = nullptr;
    if (bytes >= core::kHugePageBytes) {
      if (posix_memalign(&p, core::kHugePageBytes, bytes) != 0) throw std::bad_alloc();
      core::adviseHugePages(p, bytes);
    } else {
      p = std::malloc(bytes == 0 ? 1 : bytes);
      if (!p) throw std::bad_alloc();
    }
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) { std::free(p); }

  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  template <typename U>
  bool operator==(const BigAllocator<U>&) const {
    return true;
  }
  template <typename U>
  bool operator!=(const BigAllocator<U>&) const {
    return false;
  }
};

template <typename T>
using BigVector = std::vector<T, BigAllocator<T>>;

/// Open-addressing hash table from cell coordinates to cell index (the coordinates live in `coords`).
class CellTable {
 public:
  explicit CellTable(const BigVector<CellCoord>& coords) : coords_(coords) {
    std::size_t size = 16;
    shift_ = 60;
    while (size < 2 * coords.size()) {
      size *= 2;
      --shift_;
    }
    mask_ = size - 1;
    slots_.assign(size, kNone);
    for (Index c = 0; c < coords.size(); ++c) {
      std::size_t s = slotOf(coords[c]);
      while (slots_[s] != kNone) s = (s + 1) & mask_;
      slots_[s] = c;
    }
  }

  Index find(const CellCoord& c) const {
    std::size_t s = slotOf(c);
    while (true) {
      const Index v = slots_[s];
      if (v == kNone || coords_[v] == c) return v;
      s = (s + 1) & mask_;
    }
  }

 private:
  /// Multiplicative hashing: the top bits of a product are well mixed, and it is cheap (this runs
  /// for every cell of every stencil).
  std::size_t slotOf(const CellCoord& c) const {
    const std::uint64_t h =
        (static_cast<std::uint64_t>(c.x) * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(c.y)) *
            0xC2B2AE3D27D4EB4FULL +
        static_cast<std::uint64_t>(c.z);
    return std::size_t((h ^ (h >> 29)) * 0xD6E8FEB86659FD93ULL >> shift_);
  }

  const BigVector<CellCoord>& coords_;
  BigVector<Index> slots_;
  std::size_t mask_ = 0;
  int shift_ = 60;
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

/// Sorts (key, index) pairs, given in index order, by key then index: one parallel stable scatter
/// on the top key bits (a hash), then each bucket sorted on its own in parallel. The result is a
/// total order, independent of the thread count.

struct KeyedPoint {
  std::uint64_t key;
  Index index;
  bool operator<(const KeyedPoint& o) const { return key < o.key || (key == o.key && index < o.index); }
};

inline void sortByKey(BigVector<KeyedPoint>& items) {
  const std::size_t n = items.size();
  using Item = KeyedPoint;
  if (n < 4096) {
    std::sort(items.begin(), items.end());
    return;
  }
  constexpr int kBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  constexpr int kLowBits = 12;  // the Morton code of a cell inside its block (sortKey)
  constexpr std::size_t kLowKeys = std::size_t{1} << kLowBits;
  const std::size_t chunk = 1 << 15;
  const std::size_t chunks = (n + chunk - 1) / chunk;
  std::vector<std::uint32_t> offsets(chunks * kBuckets, 0);  // chunk-major counts, then offsets
  const auto bucketOf = [](const Item& item) { return std::size_t(item.key >> (64 - kBits)); };
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    std::uint32_t* count = &offsets[c * kBuckets];
    for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) ++count[bucketOf(items[i])];
  });
  std::vector<std::size_t> bucket_start(kBuckets + 1, 0);
  std::size_t running = 0;
  for (std::size_t b = 0; b < kBuckets; ++b) {
    bucket_start[b] = running;
    for (std::size_t c = 0; c < chunks; ++c) {
      const std::uint32_t count = offsets[c * kBuckets + b];
      offsets[c * kBuckets + b] = std::uint32_t(running);
      running += count;
    }
  }
  bucket_start[kBuckets] = running;
  BigVector<Item> sorted(n);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    std::uint32_t* next = &offsets[c * kBuckets];
    for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i)
      sorted[next[bucketOf(items[i])]++] = items[i];
  });
  // Each bucket, still in index order (the scatter is stable), goes back into `items` sorted: a
  // counting sort on the low 12 key bits (the cell inside its block; stable), then, only when the
  // bucket holds several blocks, a stable sort on the block bits.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kBuckets, 16), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<std::uint32_t> count;
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const std::size_t begin = bucket_start[b], end = bucket_start[b + 1];
      if (end - begin < 512) {
        std::copy(sorted.begin() + begin, sorted.begin() + end, items.begin() + begin);
        std::sort(items.begin() + begin, items.begin() + end);
        continue;
      }
      count.assign(kLowKeys + 1, 0);
      bool one_block = true;
      const std::uint64_t block = sorted[begin].key >> kLowBits;
      for (std::size_t i = begin; i < end; ++i) {
        ++count[(sorted[i].key & (kLowKeys - 1)) + 1];
        one_block = one_block && (sorted[i].key >> kLowBits) == block;
      }
      for (std::size_t k = 1; k <= kLowKeys; ++k) count[k] += count[k - 1];
      for (std::size_t i = begin; i < end; ++i) items[begin + count[sorted[i].key & (kLowKeys - 1)]++] = sorted[i];
      if (!one_block) {
        std::stable_sort(items.begin() + begin, items.begin() + end,
                         [](const Item& u, const Item& v) { return (u.key >> 12) < (v.key >> 12); });
      }
    }
  });
}

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
  }

  /// DBSCAN; with `k_distance`, also the core distances of its sample (DbscanResult::k_distance_curve).
  DbscanResult run(const KDistanceRequest* k_distance = nullptr) {
    buildGrid();
    std::vector<double> curve;
    if (k_distance != nullptr) curve = coreDistanceCurve(k_distance->max_samples);
    markCore();
    joinCoreCells();
    DbscanResult result = label();
    result.k_distance_curve = std::move(curve);
    return result;
  }

 private:
  CellCoord cellOf(const Eigen::Vector3d& p) const {
    // floor without the libm call (hot: it runs for every point several times); |v| < 4e18 checked.
    const auto f = [&](double v) {
      v *= inv_side_;
      const auto t = static_cast<std::int64_t>(v);
      return t - (v < static_cast<double>(t));
    };
    return CellCoord{f(p.x()), f(p.y()), D == 3 ? f(p.z()) : 0};
  }

  std::uint64_t weightOf(Index sorted) const { return input_weights_.empty() ? 1 : input_weights_[order_[sorted]]; }

  void buildGrid() {
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

  /// Core distances of the points kDistanceSample(n, max_samples) picks, sorted descending (see the
  /// dbscan() overload taking a KDistanceRequest).
  std::vector<double> coreDistanceCurve(std::size_t max_samples) {
    const std::uint64_t min_pts = std::uint64_t(params_.min_pts);
    std::uint64_t total = 0;
    for (const std::uint64_t w : cell_weight_) total += w;
    if (total < min_pts) return {};
    const std::size_t n = input_.size();
    const std::size_t count = max_samples == 0 ? n : std::min(n, max_samples);
    std::vector<double> curve(count, 0.0);
    if (min_pts > 1) {
      // The sampled points (kDistanceSample's) in grid order, by their sorted positions, so that
      // consecutive queries share cells in cache.
      std::vector<std::uint8_t> sampled(n, 0);
      for (const std::uint32_t i : kDistanceSample(n, max_samples)) sampled[i] = 1;
      std::vector<Index> queries;
      queries.reserve(count);
      for (std::size_t j = 0; j < n; ++j) {
        if (sampled[order_[j]]) queries.push_back(Index(j));
      }
      assert(queries.size() == count);
      buildGroups();
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, queries.size(), 256),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          NearestList heap;
                          std::vector<std::pair<double, std::uint64_t>> queue;
                          for (std::size_t j = r.begin(); j != r.end(); ++j) {
                            curve[j] = std::sqrt(coreDistance2(pts_[queries[j]], heap, queue));
                          }
                        });
    }
    std::sort(curve.begin(), curve.end(), std::greater<double>());
    return curve;
  }

  /// The nearest points found so far, sorted by squared distance, holding just enough weight for
  /// min_pts: bound is then the squared core distance of the points offered so far. (A sorted array:
  /// it holds about min_pts items, so an insertion moves a few of them, cheaper than a heap's sifts.)
  struct NearestList {
    std::vector<std::pair<double, std::uint64_t>> items;  // (squared distance, weight), ascending
    std::uint64_t held = 0;
    double bound = std::numeric_limits<double>::infinity();

    void clear() {
      items.clear();
      held = 0;
      bound = std::numeric_limits<double>::infinity();
    }
    void offer(double d2, std::uint64_t weight, std::uint64_t min_pts) {
      if (d2 >= bound) return;  // cannot lower the core distance
      items.emplace_back(d2, weight);
      for (std::size_t i = items.size() - 1; i > 0 && items[i - 1].first > d2; --i) std::swap(items[i - 1], items[i]);
      held += weight;
      while (held - items.back().second >= min_pts) {  // the farthest is not needed any more
        held -= items.back().second;
        items.pop_back();
      }
      if (held >= min_pts) bound = items.back().first;
    }
  };

  /// Cells grouped by their 16^d-cell block (a block's cells are contiguous in cell order: the sort
  /// key's high bits are the block's hash; two blocks sharing a hash make two groups, each a run), with
  /// the union of their boxes.
  void buildGroups() {
    group_start_.clear();
    group_boxes_.clear();
    const std::size_t cells = coords_.size();
    const auto block = [&](std::size_t c) {
      return CellCoord{coords_[c].x >> 4, coords_[c].y >> 4, coords_[c].z >> 4};
    };
    for (std::size_t c = 0; c < cells; ++c) {
      if (c == 0 || !(block(c) == block(c - 1))) {
        group_start_.push_back(Index(c));
        group_boxes_.push_back(boxes_[c]);
      } else {
        CellBox& g = group_boxes_.back();
        for (int k = 0; k < 3; ++k) {
          g.lo[k] = std::min(g.lo[k], boxes_[c].lo[k]);
          g.hi[k] = std::max(g.hi[k], boxes_[c].hi[k]);
        }
      }
    }
    group_start_.push_back(Index(cells));
  }

  /// Squared core distance of p (see coreDistanceCurve): the 3^d cells around p's own first; then,
  /// unless no point outside them can be nearer than the bound found, the groups nearest first.
  double coreDistance2(const Eigen::Vector3d& p, NearestList& heap,
                       std::vector<std::pair<double, std::uint64_t>>& queue) const {
    const std::uint64_t min_pts = std::uint64_t(params_.min_pts);
    heap.clear();
    const auto scanCell = [&](Index o) {
      if (minSquaredDistance<D>(p, boxes_[o]) > heap.bound) return;
      for (Index q = start_[o]; q < start_[o + 1]; ++q) {
        heap.offer(squaredDistance<D>(p, pts_[q]), weightOf(q), min_pts);
      }
    };
    const CellCoord base = cellOf(p);
    // gap2[k][o + 1]: squared gap along axis k from p to the cell at offset o (0 for its own); every
    // point outside the 3^d cells is at least `reach` away along some axis. The slack covers rounding
    // in the cell assignment, so gaps are never overestimated.
    double gap2[3][3] = {};
    double reach = std::numeric_limits<double>::infinity();
    for (int k = 0; k < D; ++k) {
      const double slack = side_ * 1e-6 + 1e-14 * std::abs(p[k]);
      const double below = std::max(0.0, p[k] - double(base[k]) * side_ - slack);
      const double above = std::max(0.0, double(base[k] + 1) * side_ - p[k] - slack);
      gap2[k][0] = below * below;
      gap2[k][2] = above * above;
      reach = std::min(reach, std::min(below, above) + side_ * (1.0 - 1e-6));
    }
    // Its own cell first (the bound it gives skips most neighbours unlooked-up), then the others.
    if (const Index own = table_->find(base); own != kNone) scanCell(own);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = (D == 2 ? 0 : -1); dz <= (D == 2 ? 0 : 1); ++dz) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          if (gap2[0][dx + 1] + gap2[1][dy + 1] + gap2[2][dz + 1] > heap.bound) continue;
          const Index o = table_->find(CellCoord{base.x + dx, base.y + dy, base.z + dz});
          if (o != kNone) scanCell(o);
        }
      }
    }
    if (heap.bound <= reach * reach) return heap.bound;

    // Best first over groups and cells together: a min-heap on the squared distance to the box,
    // where popping a group pushes its cells, popped only as far as the bound reaches. An isolated
    // point has every group as a candidate and needs only the nearest few cells.
    const std::uint64_t group_count = group_start_.size() - 1;  // ids >= group_count are cells
    queue.clear();
    for (std::uint64_t g = 0; g < group_count; ++g) {
      const double d2 = minSquaredDistance<D>(p, group_boxes_[g]);
      if (d2 <= heap.bound) queue.emplace_back(d2, g);
    }
    const auto farther = [](const std::pair<double, std::uint64_t>& a, const std::pair<double, std::uint64_t>& b) {
      return a > b;
    };
    std::make_heap(queue.begin(), queue.end(), farther);
    const auto near = [&](const CellCoord& c) {
      return std::abs(c.x - base.x) <= 1 && std::abs(c.y - base.y) <= 1 && std::abs(c.z - base.z) <= 1;
    };
    while (!queue.empty() && queue.front().first <= heap.bound) {
      const std::uint64_t id = queue.front().second;
      std::pop_heap(queue.begin(), queue.end(), farther);
      queue.pop_back();
      if (id >= group_count) {  // a cell: id - group_count
        const auto o = Index(id - group_count);
        for (Index q = start_[o]; q < start_[o + 1]; ++q) {
          heap.offer(squaredDistance<D>(p, pts_[q]), weightOf(q), min_pts);
        }
        continue;
      }
      for (Index o = group_start_[id]; o < group_start_[id + 1]; ++o) {
        if (near(coords_[o])) continue;  // the 3^d cells around p were scanned above
        const double d2 = minSquaredDistance<D>(p, boxes_[o]);
        if (d2 <= heap.bound) {
          queue.emplace_back(d2, group_count + o);
          std::push_heap(queue.begin(), queue.end(), farther);
        }
      }
    }
    return heap.bound;
  }

  /// Existing cells of the stencil around `c` that can hold a point within eps of one of c's points,
  /// judged from c's bounding box and the extent of the other cell, nearest offsets first. With
  /// `forward_only`, only the offsets after (0,0,0) in lexicographic order: each pair of cells once.
  int neighbours(Index c, std::array<Index, 124>& out, bool forward_only = false) const {
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

  BigVector<Eigen::Vector3d> pts_;        // points sorted by cell
  BigVector<Index> order_;                // sorted position -> input index
  BigVector<Index> start_;                // cell -> first sorted position; size cells + 1
  BigVector<CellCoord> coords_;           // cell -> grid coordinates
  BigVector<CellBox> boxes_;              // cell -> bounding box of its points
  BigVector<std::uint64_t> cell_weight_;  // cell -> summed weight
  std::unique_ptr<CellTable> table_;
  BigVector<std::uint8_t> core_;       // sorted position -> core
  BigVector<std::uint8_t> cell_core_;  // cell -> kNoCore, kSomeCore, kAllCore
  std::unique_ptr<UnionFind> sets_;
  std::vector<Index> group_start_;    // group -> first cell; size groups + 1 (k-distance only)
  std::vector<CellBox> group_boxes_;  // group -> bounding box of its cells
};

}  // namespace
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
