#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "grid_dbscan.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/core/kd_tree.hpp"

// The k-distance curve needs k nearest neighbours without knowing a radius, so a grid does not fit
// (its cell size would have to be guessed, and gross outliers would need unbounded ring searches):
// nanoflann's k-d tree (exact k nearest, the squared distance summed per axis in axis order as the
// brute-force definition sums it) answers each query in about O(log n + k).

namespace hullmap::clustering {
namespace {

template <int D>
using KdTree = core::PointKdTree<D>;

/// curve[j] = distance from points[queries[j]] to its (k+1)-th nearest point, itself included.
template <int D>
void kthDistances(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& queries, int k,
                  std::vector<double>& curve) {
  const core::PointsAdaptor cloud{points};
  const KdTree<D> tree(D, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(32));
  const std::size_t want = static_cast<std::size_t>(k) + 1;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, queries.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::vector<std::uint32_t> indices(want);
                      std::vector<double> squared(want);
                      for (std::size_t j = r.begin(); j != r.end(); ++j) {
                        const Eigen::Vector3d& q = points[queries[j]];
                        const double query[3] = {q.x(), q.y(), q.z()};
                        const std::size_t found = tree.knnSearch(query, want, indices.data(), squared.data());
                        curve[j] = std::sqrt(squared[found - 1]);
                      }
                    });
}

}  // namespace

std::vector<std::uint32_t> kDistanceSample(std::size_t n, std::size_t max_samples) {
  const std::size_t count = max_samples == 0 ? n : std::min(n, max_samples);
  std::vector<std::uint32_t> sample(count);
  for (std::size_t j = 0; j < count; ++j) {
    // Evenly spread over the input: floor(j * n / count), exact in 128 bits.
    sample[j] = static_cast<std::uint32_t>(static_cast<unsigned __int128>(j) * n / count);
  }
  return sample;
}

std::vector<double> kDistanceCurve(const std::vector<Eigen::Vector3d>& points, int min_pts, Metric metric,
                                   std::size_t max_samples) {
  if (min_pts < 1) throw Error::inParameter("min_pts", "must be >= 1, got " + std::to_string(min_pts));
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) throw Error("k-distance: point " + std::to_string(i) + " is not finite");
  }
  const int k = min_pts - 1;
  if (points.size() < static_cast<std::size_t>(min_pts)) return {};
  const std::vector<std::uint32_t> queries = kDistanceSample(points.size(), max_samples);
  std::vector<double> curve(queries.size(), 0.0);
  if (k == 0) return curve;
  if (metric == Metric::kXy) {
    kthDistances<2>(points, queries, k, curve);
  } else {
    kthDistances<3>(points, queries, k, curve);
  }
  tbb::parallel_sort(curve.begin(), curve.end(), std::greater<double>());
  return curve;
}

double suggestEps(const std::vector<double>& curve) {
  if (curve.empty()) return 0.0;
  const std::size_t skip = curve.size() / 100;
  const std::size_t first = skip;
  const std::size_t last = curve.size() - 1;
  if (last <= first + 1) return curve[first];
  const double y0 = curve[first], y1 = curve[last];
  if (!(y0 > y1)) return curve[first];
  // Scaled to [0,1]: x = (i - first) / (last - first), y = (v - y1) / (y0 - y1); the chord is y = 1 - x,
  // and a point's distance below it is proportional to (1 - x) - y.
  double best_gap = -1.0;
  std::size_t best = first;
  for (std::size_t i = first; i <= last; ++i) {
    const double x = double(i - first) / double(last - first);
    const double y = (curve[i] - y1) / (y0 - y1);
    const double gap = (1.0 - x) - y;
    if (gap > best_gap) {
      best_gap = gap;
      best = i;
    }
  }
  return curve[best];
}

namespace detail {

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

template <int D>
std::vector<double> GridDbscan<D>::coreDistanceCurve(std::size_t max_samples) {
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

template <int D>
void GridDbscan<D>::buildGroups() {
  group_start_.clear();
  group_boxes_.clear();
  const std::size_t cells = coords_.size();
  const auto block = [&](std::size_t c) { return CellCoord{coords_[c].x >> 4, coords_[c].y >> 4, coords_[c].z >> 4}; };
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

template <int D>
double GridDbscan<D>::coreDistance2(const Eigen::Vector3d& p, NearestList& heap,
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

template std::vector<double> GridDbscan<2>::coreDistanceCurve(std::size_t max_samples);
template std::vector<double> GridDbscan<3>::coreDistanceCurve(std::size_t max_samples);

}  // namespace detail

}  // namespace hullmap::clustering
