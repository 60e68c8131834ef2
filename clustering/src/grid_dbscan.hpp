#pragma once

// The grid DBSCAN's engine, shared by dbscan.cpp (the grid, the core pass, the union of core cells,
// the labels) and dbscan_kdistance.cpp (the core distances of a sample).
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/big_allocator.hpp"
#include "hullmap/core/lattice.hpp"
#include "union_find.hpp"

namespace hullmap::clustering::detail {

using core::BigVector;

using Index = std::uint32_t;
inline constexpr Index kNone = std::numeric_limits<Index>::max();

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

struct NearestList;

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

  void buildGrid();

  /// Core distances of the points kDistanceSample(n, max_samples) picks, sorted descending (see the
  /// dbscan() overload taking a KDistanceRequest).
  std::vector<double> coreDistanceCurve(std::size_t max_samples);

  /// Cells grouped by their 16^d-cell block (a block's cells are contiguous in cell order: the sort
  /// key's high bits are the block's hash; two blocks sharing a hash make two groups, each a run), with
  /// the union of their boxes.
  void buildGroups();

  /// Squared core distance of p (see coreDistanceCurve): the 3^d cells around p's own first; then,
  /// unless no point outside them can be nearer than the bound found, the groups nearest first.
  double coreDistance2(const Eigen::Vector3d& p, NearestList& heap,
                       std::vector<std::pair<double, std::uint64_t>>& queue) const;

  /// Existing cells of the stencil around `c` that can hold a point within eps of one of c's points,
  /// judged from c's bounding box and the extent of the other cell, nearest offsets first. With
  /// `forward_only`, only the offsets after (0,0,0) in lexicographic order: each pair of cells once.
  int neighbours(Index c, std::array<Index, 124>& out, bool forward_only = false) const;

  void markCore();

  /// True when some core point of a is within eps of some core point of b (early exit).
  bool coreLinked(Index a, Index b) const;

  void joinCoreCells();

  /// Nearest core neighbour of the non-core point j of cell c (ties: first in the input), or kNone.
  Index nearestCore(Index j, Index c, const std::array<Index, 124>& near, int m) const;

  DbscanResult label();

  /// The cell holding sorted position q, known to be c or one of its neighbours.
  Index cellOfSorted(Index q, Index c, const std::array<Index, 124>& near, int m) const;

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

}  // namespace hullmap::clustering::detail
