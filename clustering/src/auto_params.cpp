#include "hullmap/clustering/auto_params.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "hullmap/core/error.hpp"
#include "hullmap/core/lattice.hpp"
#include "hullmap/core/random.hpp"

namespace hullmap::clustering {
namespace {

using core::Cell;
using core::CellHash;

void checkRule(const AutoParamsRule& r, double resolution) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw Error::inParameter("eps", "auto: " + what);
  };
  require(std::isfinite(resolution) && resolution > 0.0, "the resolution must be finite and > 0");
  require(r.k >= 1, "k must be >= 1");
  require(std::isfinite(r.knn_quantile) && r.knn_quantile >= 0.0 && r.knn_quantile <= 1.0,
          "knn_quantile must be in [0, 1]");
  require(std::isfinite(r.eps_factor) && r.eps_factor > 0.0, "eps_factor must be finite and > 0");
  require(std::isfinite(r.min_eps_voxels) && r.min_eps_voxels > 0.0 && std::isfinite(r.max_eps_voxels) &&
              r.max_eps_voxels >= r.min_eps_voxels,
          "the eps clamp must satisfy 0 < min_eps_voxels <= max_eps_voxels");
  require(std::isfinite(r.min_pts_quantile) && r.min_pts_quantile >= 0.0 && r.min_pts_quantile <= 1.0,
          "min_pts_quantile must be in [0, 1]");
  require(r.min_min_pts >= 1, "min_min_pts must be >= 1");
  require(r.sample >= 1, "the sample must hold at least one voxel");
}

// The sample: all voxels, or `rule.sample` drawn with a fixed seed (portable: 128-bit multiply).
std::vector<std::size_t> sampleVoxels(std::size_t voxels, const AutoParamsRule& rule) {
  std::vector<std::size_t> sample;
  if (voxels <= rule.sample) {
    sample.resize(voxels);
    for (std::size_t i = 0; i < sample.size(); ++i) sample[i] = i;
    return sample;
  }
  core::RandomDraws draws(rule.seed);
  sample.reserve(rule.sample);
  for (std::size_t i = 0; i < rule.sample; ++i) sample.push_back(draws.index(voxels));
  return sample;
}

// The voxels within max_eps of each sampled voxel, found through cells of side max_eps: every
// neighbour within max_eps is in the 27 cells around a voxel's cell (9 under kXy, where z is 0).
// Cells far out of int range (gross outliers) are clamped: they only ever hold far-away voxels.
class SampleNeighbours {
 public:
  SampleNeighbours(const std::vector<Eigen::Vector3d>& centres, const std::vector<std::size_t>& sample, double max_eps,
                   bool xy)
      : centres_(centres), sample_(sample), max_eps_(max_eps), xy_(xy) {
    // Gather the voxels in the cells around the sample.
    for (std::size_t s : sample) {
      const Cell c = cellOf(position(s));
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = xy ? 0 : -1; dz <= (xy ? 0 : 1); ++dz) grid_.try_emplace(Cell{c.x + dx, c.y + dy, c.z + dz});
    }
    for (std::size_t i = 0; i < centres.size(); ++i) {
      const auto it = grid_.find(cellOf(position(i)));
      if (it != grid_.end()) it->second.push_back(static_cast<std::uint32_t>(i));
    }
  }

  // Calls f(squared distance, index) for every voxel within max_eps of sampled voxel j (itself
  // included, at 0; under kXy so are voxels stacked above it: DBSCAN counts them too).
  template <class F>
  void forEachNear(std::size_t j, F&& f) const {
    const double max_eps2 = max_eps_ * max_eps_;
    const Eigen::Vector3d p = position(sample_[j]);
    const Cell c = cellOf(p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = xy_ ? 0 : -1; dz <= (xy_ ? 0 : 1); ++dz) {
          for (std::uint32_t i : grid_.at(Cell{c.x + dx, c.y + dy, c.z + dz})) {
            const double d2 = (position(i) - p).squaredNorm();
            if (d2 <= max_eps2) f(d2, i);
          }
        }
  }

 private:
  Eigen::Vector3d position(std::size_t i) const {
    Eigen::Vector3d p = centres_[i];
    if (xy_) p.z() = 0.0;
    return p;
  }
  Cell cellOf(const Eigen::Vector3d& p) const {
    auto axis = [&](double v) { return static_cast<std::int64_t>(std::clamp(std::floor(v / max_eps_), -1e9, 1e9)); };
    return Cell{axis(p.x()), axis(p.y()), axis(p.z())};
  }

  const std::vector<Eigen::Vector3d>& centres_;
  const std::vector<std::size_t>& sample_;
  double max_eps_;
  bool xy_;
  std::unordered_map<Cell, std::vector<std::uint32_t>, CellHash> grid_;
};

// Pass 1: each sampled voxel's distance to its k-th nearest other voxel (the (k+1)-th smallest
// distance, a max-heap of k + 1); infinity when it has fewer within max_eps.
std::vector<double> kthNeighbourDistances(const SampleNeighbours& near, std::size_t sampled, int k) {
  const auto k1 = static_cast<std::size_t>(k) + 1;
  std::vector<double> knn(sampled, std::numeric_limits<double>::infinity());
  std::vector<double> heap;
  for (std::size_t j = 0; j < sampled; ++j) {
    heap.clear();
    near.forEachNear(j, [&](double d2, std::uint32_t) {
      if (heap.size() < k1) {
        heap.push_back(d2);
        std::push_heap(heap.begin(), heap.end());
      } else if (d2 < heap.front()) {
        std::pop_heap(heap.begin(), heap.end());
        heap.back() = d2;
        std::push_heap(heap.begin(), heap.end());
      }
    });
    if (heap.size() == k1) knn[j] = std::sqrt(heap.front());
  }
  return knn;
}

// The knn_quantile of the k-th neighbour distances weighted by the voxels' map points: the spacing
// around the typical map point. A dense map's outliers occupy a voxel each, one point in it, and can
// be most of the voxels; counted per voxel they would set eps to their own spacing.
double weightedKnnQuantile(const std::vector<double>& knn, const std::vector<std::size_t>& sample,
                           const std::vector<std::uint32_t>& weights, double quantile) {
  std::vector<std::pair<double, double>> by_distance(sample.size());
  double total = 0.0;
  for (std::size_t j = 0; j < sample.size(); ++j) {
    const double w = weights.empty() ? 1.0 : static_cast<double>(weights[sample[j]]);
    by_distance[j] = {knn[j], w};
    total += w;
  }
  std::sort(by_distance.begin(), by_distance.end());
  double below = 0.0;
  for (const auto& [d, w] : by_distance) {
    below += w;
    if (below >= quantile * total * (1.0 - 1e-12)) return d;
  }
  return by_distance.back().first;
}

// Pass 2: neighbourhood weights at eps, with DBSCAN's test (squared distance <= eps^2), over the
// sampled voxels that lie on a structure: k other voxels within eps (isolated outliers would
// otherwise drag the quantile down to 1 on maps with many of them). Sets out.structured and, when
// any voxel is on a structure, out.min_pts: the min_pts_quantile of those weights, weighted by the
// sampled voxel's own map points as eps's is.
void chooseMinPts(const SampleNeighbours& near, const std::vector<std::size_t>& sample,
                  const std::vector<std::uint32_t>& weights, const AutoParamsRule& rule, AutoParams& out) {
  const double eps2 = out.eps * out.eps;
  std::vector<std::pair<double, double>> weight;  // (neighbourhood weight, the voxel's weight)
  double total_weight = 0.0;
  for (std::size_t j = 0; j < sample.size(); ++j) {
    std::size_t count = 0;
    double sum = 0.0;
    near.forEachNear(j, [&](double d2, std::uint32_t i) {
      if (d2 <= eps2) {
        ++count;
        sum += weights.empty() ? 1.0 : static_cast<double>(weights[i]);
      }
    });
    if (count > static_cast<std::size_t>(rule.k)) {
      const double own = weights.empty() ? 1.0 : static_cast<double>(weights[sample[j]]);
      weight.emplace_back(sum, own);
      total_weight += own;
    }
  }
  out.structured = weight.size();
  if (weight.empty()) return;
  std::sort(weight.begin(), weight.end());
  double chosen = weight.back().first, below_weight = 0.0;
  for (const auto& [sum, own] : weight) {
    below_weight += own;
    if (below_weight > rule.min_pts_quantile * total_weight * (1.0 + 1e-12)) {
      chosen = sum;
      break;
    }
  }
  chosen = std::min(chosen, static_cast<double>(std::numeric_limits<int>::max()));
  out.min_pts = std::max(rule.min_min_pts, static_cast<int>(chosen));
}

}  // namespace

AutoParams chooseDbscanParams(const std::vector<Eigen::Vector3d>& centres, const std::vector<std::uint32_t>& weights,
                              double resolution, Metric metric, const AutoParamsRule& rule) {
  checkRule(rule, resolution);
  if (!weights.empty() && weights.size() != centres.size()) {
    throw Error::inParameter("eps", "auto: " + std::to_string(weights.size()) + " weights for " +
                                        std::to_string(centres.size()) + " voxels");
  }
  for (const auto& c : centres) {
    if (!c.allFinite()) throw Error::inParameter("eps", "auto: non-finite voxel centre");
  }
  AutoParams out;
  const double max_eps = rule.max_eps_voxels * resolution;
  const double min_eps = rule.min_eps_voxels * resolution;
  out.eps = min_eps;
  out.min_pts = rule.min_min_pts;
  if (centres.empty()) {
    out.knn = std::numeric_limits<double>::infinity();
    out.eps_unclamped = out.knn;
    return out;
  }
  const std::vector<std::size_t> sample = sampleVoxels(centres.size(), rule);
  out.sampled = sample.size();
  const SampleNeighbours near(centres, sample, max_eps, metric == Metric::kXy);
  const std::vector<double> knn = kthNeighbourDistances(near, sample.size(), rule.k);
  out.knn = weightedKnnQuantile(knn, sample, weights, rule.knn_quantile);
  out.eps_unclamped = rule.eps_factor * out.knn;
  out.eps = std::clamp(out.eps_unclamped, min_eps, max_eps);
  chooseMinPts(near, sample, weights, rule, out);
  return out;
}

}  // namespace hullmap::clustering
