#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

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

}  // namespace hullmap::clustering
