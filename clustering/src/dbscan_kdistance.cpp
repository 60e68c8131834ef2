#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"

// The k-distance curve needs k nearest neighbours without knowing a radius, so a grid does not fit
// (its cell size would have to be guessed, and gross outliers would need unbounded ring searches).
// A bucketed kd-tree with median splits is O(n log n) to build and answers every query in about
// O(log n + k) whatever the spread of the cloud.

namespace hullmap::clustering {
namespace detail {
namespace {

constexpr std::size_t kLeafSize = 12;

class KdTree {
 public:
  KdTree(const std::vector<Eigen::Vector3d>& points, int dims) : points_(points), dims_(dims) {
    index_.resize(points.size());
    for (std::size_t i = 0; i < index_.size(); ++i) index_[i] = static_cast<std::uint32_t>(i);
    nodes_.reserve(2 * points.size() / kLeafSize + 2);
    build(0, index_.size());
  }

  /// Squared distance from point i to its (k+1)-th nearest point, itself included (so the k-th
  /// nearest other point; duplicates count). `best` is scratch space of the caller.
  double kthSquaredDistance(std::size_t i, int k, std::vector<double>& best) const {
    best.clear();
    search(0, points_[i], static_cast<std::size_t>(k) + 1, best);
    return best.back();
  }

  /// The points in tree order (spatially coherent): querying in this order keeps caches warm.
  const std::vector<std::uint32_t>& treeOrder() const { return index_; }

 private:
  struct Node {
    std::uint32_t begin = 0, end = 0;  // leaf range in index_
    std::int32_t left = -1, right = -1;
    int axis = -1;                     // -1 for a leaf
    double split = 0.0;
  };

  double squaredDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    double s = 0.0;
    for (int k = 0; k < dims_; ++k) {
      const double d = a[k] - b[k];
      s += d * d;
    }
    return s;
  }

  std::int32_t build(std::size_t begin, std::size_t end) {
    const auto id = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back(Node{static_cast<std::uint32_t>(begin), static_cast<std::uint32_t>(end)});
    if (end - begin <= kLeafSize) return id;
    Eigen::Vector3d lo = points_[index_[begin]], hi = lo;
    for (std::size_t j = begin; j < end; ++j) {
      lo = lo.cwiseMin(points_[index_[j]]);
      hi = hi.cwiseMax(points_[index_[j]]);
    }
    int axis = 0;
    for (int k = 1; k < dims_; ++k) {
      if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
    }
    if (!(hi[axis] > lo[axis])) return id;  // all duplicates: keep as one leaf
    const std::size_t mid = begin + (end - begin) / 2;
    std::nth_element(index_.begin() + begin, index_.begin() + mid, index_.begin() + end,
                     [&](std::uint32_t a, std::uint32_t b) { return points_[a][axis] < points_[b][axis]; });
    const double split = points_[index_[mid]][axis];
    const std::int32_t left = build(begin, mid);
    const std::int32_t right = build(mid, end);
    Node& node = nodes_[id];
    node.axis = axis;
    node.split = split;
    node.left = left;
    node.right = right;
    return id;
  }

  void search(std::int32_t id, const Eigen::Vector3d& q, std::size_t want, std::vector<double>& best) const {
    const Node& node = nodes_[id];
    if (node.axis < 0) {
      // `best` holds the smallest squared distances so far, ascending, at most `want` of them.
      for (std::uint32_t j = node.begin; j < node.end; ++j) {
        const double d = squaredDistance(q, points_[index_[j]]);
        if (best.size() == want) {
          if (!(d < best.back())) continue;
          best.pop_back();
        }
        best.insert(std::upper_bound(best.begin(), best.end(), d), d);
      }
      return;
    }
    // Left holds coordinates <= split, right >= split (nth_element), so the plane bound is exact.
    const double diff = q[node.axis] - node.split;
    const std::int32_t near = diff < 0 ? node.left : node.right;
    const std::int32_t far = diff < 0 ? node.right : node.left;
    search(near, q, want, best);
    if (best.size() < want || diff * diff <= best.back()) search(far, q, want, best);
  }

  const std::vector<Eigen::Vector3d>& points_;
  int dims_;
  std::vector<std::uint32_t> index_;
  std::vector<Node> nodes_;
};

}  // namespace
}  // namespace detail

std::vector<double> kDistanceCurve(const std::vector<Eigen::Vector3d>& points, int min_pts, Metric metric) {
  if (min_pts < 1) throw Error::inParameter("min_pts", "must be >= 1, got " + std::to_string(min_pts));
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) throw Error("k-distance: point " + std::to_string(i) + " is not finite");
  }
  const int k = min_pts - 1;
  if (points.size() < static_cast<std::size_t>(min_pts)) return {};
  std::vector<double> curve(points.size(), 0.0);
  if (k == 0) return curve;
  const detail::KdTree tree(points, metric == Metric::kXy ? 2 : 3);
  const auto& order = tree.treeOrder();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::vector<double> best;
                      best.reserve(static_cast<std::size_t>(k) + 2);
                      for (std::size_t j = r.begin(); j != r.end(); ++j) {
                        const std::size_t i = order[j];
                        curve[i] = std::sqrt(tree.kthSquaredDistance(i, k, best));
                      }
                    });
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

}  // namespace hullmap::clustering
