#include "hullmap/hulls/convex_parts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <queue>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include <tbb/parallel_for.h>

#include "cluster_splitter.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/core/kd_tree.hpp"
#include "hullmap/hulls/detail/lattice_hull.hpp"

namespace hullmap::hulls {
namespace {

using detail::Check;
using detail::ClusterSplitter;
using detail::inside;
using detail::LatticePoint;
using detail::Members;

/// Adapted flat gap (ConvexPartsParams::adapt_flat_gap): clusters of fewer voxels keep G; at most
/// this many voxels are sampled for the density; the expected number of empty discs of the adapted
/// radius that chance leaves on the cluster's surface; the cap, a multiple of G.
constexpr std::size_t kAdaptMinVoxels = 16;
constexpr std::size_t kAdaptSamples = 1024;
constexpr double kAdaptVacancies = 0.01;
constexpr double kAdaptMaxFactor = 2.0;

/// A cluster on its lattice: cells sorted as the centres are given.
struct ClusterLattice {
  Eigen::Vector3d origin;  ///< corner (0, 0, 0), map frame
  std::vector<LatticePoint> cells;
};

ClusterLattice toLattice(const std::vector<Eigen::Vector3d>& centers, double voxel_size) {
  ClusterLattice lattice;
  // The same origin as buildObstacles: the lower corner of the lexicographically smallest centre.
  const auto anchor =
      std::min_element(centers.begin(), centers.end(), [](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
        return std::tie(p.x(), p.y(), p.z()) < std::tie(q.x(), q.y(), q.z());
      });
  lattice.origin = *anchor - Eigen::Vector3d::Constant(0.5 * voxel_size);
  for (const auto& c : centers) lattice.cells.push_back(detail::latticeIndex(c, lattice.origin, voxel_size));
  return lattice;
}

double resolveConcavity(const ConvexPartsParams& params, double voxel_size) {
  if (!(voxel_size > 0) || !std::isfinite(voxel_size))
    throw Error("convex parts: voxel_size must be positive, got " + std::to_string(voxel_size));
  if (!(params.concavity >= 0) || !std::isfinite(params.concavity))
    throw Error("convex parts: concavity must be >= 0 (0: default), got " + std::to_string(params.concavity));
  return params.concavity > 0 ? params.concavity : defaultConcavity(voxel_size);
}

/// G: the flat parts' bound, at least T (T when unset: no relaxation).
double resolveFlatGap(const ConvexPartsParams& params, double t) {
  if (params.flat_gap && (!(*params.flat_gap >= 0) || !std::isfinite(*params.flat_gap)))
    throw Error("convex parts: flat_gap must be >= 0, got " + std::to_string(*params.flat_gap));
  return std::max(t, params.flat_gap.value_or(t));
}

void checkFloor(const ConvexPartsParams& params) {
  if (params.floor_z && !std::isfinite(*params.floor_z))
    throw Error("convex parts: floor_z must be finite, got " + std::to_string(*params.floor_z));
}

struct SplitResult {
  ClusterLattice lattice;
  std::vector<std::pair<Members, Check>> parts;
  double flat_gap = 0.0;  ///< the G used for this cluster, map units
};

/// x = pi lambda R^2 (the expected number of sites in a disc of radius R) at which N sites spread
/// uniformly over an area leave, in expectation, `vacancies` empty discs of radius R (Hall 1988: about
/// N x e^-x of them): the root x >= 1 of x - ln x = ln N - ln vacancies.
double chanceDiscSites(double sites, double vacancies) {
  const double target = std::log(std::max(sites, 3.0)) - std::log(vacancies);
  double x = std::max(target, 1.0);
  for (int i = 0; i < 64; ++i) x = target + std::log(x);
  return x;
}

}  // namespace

double adaptedFlatGap(const std::vector<Eigen::Vector3d>& centers, double voxel_size, const ConvexPartsParams& params) {
  const double t = resolveConcavity(params, voxel_size);
  const double g = resolveFlatGap(params, t);
  if (!params.adapt_flat_gap || !(g > t) || centers.size() < kAdaptMinVoxels) return g;
  for (std::size_t i = 0; i < centers.size(); ++i)
    if (!centers[i].allFinite()) throw Error("convex parts: non-finite voxel centre at index " + std::to_string(i));
  const ClusterLattice lattice = toLattice(centers, voxel_size);
  // The cells as sorted packed keys (21 bits per axis, offset so that a ball around any cell stays
  // non-negative), for the counts below.
  // G in cells, with a relative 1e-9 so that G = 6 voxels in map units counts the cells 6 away.
  const double r_cells = g / voxel_size;
  const double r2_cells = r_cells * r_cells * (1.0 + 1e-9);
  const std::int64_t reach = std::int64_t(std::floor(std::sqrt(r2_cells)));
  const auto key = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return (std::uint64_t(i + reach + 1) << 42) | (std::uint64_t(j + reach + 1) << 21) | std::uint64_t(k + reach + 1);
  };
  std::int64_t span = 0;
  for (const auto& c : lattice.cells) span = std::max({span, c[0], c[1], c[2]});
  if (span + 2 * reach + 2 >= (std::int64_t(1) << 21)) return g;  // too wide to pack: no adaptation
  std::vector<std::uint64_t> keys;
  keys.reserve(lattice.cells.size());
  for (const auto& c : lattice.cells) keys.push_back(key(c[0], c[1], c[2]));
  std::sort(keys.begin(), keys.end());
  std::vector<LatticePoint> ball;
  for (std::int64_t i = -reach; i <= reach; ++i)
    for (std::int64_t j = -reach; j <= reach; ++j)
      for (std::int64_t k = -reach; k <= reach; ++k)
        if ((i != 0 || j != 0 || k != 0) && double(i * i + j * j + k * k) <= r2_cells) ball.push_back({i, j, k});
  // Neighbours within G of every stride-th cell (at most kAdaptSamples of them, deterministic).
  const std::size_t stride = (lattice.cells.size() + kAdaptSamples - 1) / kAdaptSamples;
  std::vector<std::size_t> counts;
  for (std::size_t s = 0; s < lattice.cells.size(); s += stride) {
    const LatticePoint& c = lattice.cells[s];
    std::size_t count = 0;
    for (const auto& o : ball)
      count += std::binary_search(keys.begin(), keys.end(), key(c[0] + o[0], c[1] + o[1], c[2] + o[2]));
    counts.push_back(count);
  }
  // The lower quartile: the sparser stretches of the surface, not its dense edges.
  std::nth_element(counts.begin(), counts.begin() + std::ptrdiff_t(counts.size() / 4), counts.end());
  const double neighbours = std::max(1.0, double(counts[counts.size() / 4]));
  const double lambda_pi = neighbours / (r_cells * r_cells);  // pi lambda, sites per cell^2 times pi
  const double x = chanceDiscSites(double(lattice.cells.size()), kAdaptVacancies);
  const double r_chance = std::sqrt(x / lambda_pi);  // cells
  const double t_cells = t / voxel_size;
  const double adapted = std::sqrt(r_chance * r_chance + t_cells * t_cells) * voxel_size;
  return std::clamp(adapted, g, kAdaptMaxFactor * g);
}

namespace {

SplitResult splitCluster(const std::vector<Eigen::Vector3d>& centers, double voxel_size, double t,
                         const ConvexPartsParams& params, const std::vector<Eigen::Vector3d>& keyframes) {
  SplitResult result;
  if (centers.empty()) return result;
  for (std::size_t i = 0; i < centers.size(); ++i)
    if (!centers[i].allFinite()) throw Error("convex parts: non-finite voxel centre at index " + std::to_string(i));
  result.lattice = toLattice(centers, voxel_size);
  Eigen::Vector3d lo = centers[0], hi = centers[0];
  for (const auto& c : centers) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  std::vector<Eigen::Vector3d> near;
  for (const auto& k : keyframes) {
    if (!k.allFinite()) throw Error("convex parts: non-finite keyframe position");
    if ((k.array() >= lo.array() - voxel_size).all() && (k.array() <= hi.array() + voxel_size).all())
      near.push_back((k - result.lattice.origin) / voxel_size);
  }
  std::optional<double> floor_k;
  if (params.floor_z) floor_k = (*params.floor_z - result.lattice.origin.z()) / voxel_size;
  result.flat_gap = adaptedFlatGap(centers, voxel_size, params);
  ClusterSplitter splitter(result.lattice.cells, t / voxel_size, result.flat_gap / voxel_size, params.max_check_cells,
                           std::move(near), params.fill_enclosed, floor_k, params.face_holes);
  result.parts = splitter.run();
  return result;
}

}  // namespace

double defaultConcavity(double voxel_size) { return 3.0 * voxel_size; }

std::vector<std::vector<std::size_t>> splitConvexParts(const std::vector<Eigen::Vector3d>& centers, double voxel_size,
                                                       const ConvexPartsParams& params,
                                                       const std::vector<Eigen::Vector3d>& keyframes) {
  const double t = resolveConcavity(params, voxel_size);
  resolveFlatGap(params, t);  // throws on a bad flat_gap
  checkFloor(params);
  const SplitResult result = splitCluster(centers, voxel_size, t, params, keyframes);
  std::vector<std::vector<std::size_t>> out;
  for (const auto& [members, check] : result.parts) out.emplace_back(members.begin(), members.end());
  return out;
}

namespace {

/// Which parts of one cluster the stray-part rule drops (see StrayParts): flags per part.
class StrayRule {
 public:
  StrayRule(const StrayParts& rule, const std::vector<Eigen::Vector3d>& centers, double t)
      : rule_(rule),
        reach2_(std::pow(rule.support_reach > 0.0 ? rule.support_reach : 2.0 * t, 2)),
        cloud_{rule.support},
        tree_(3, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    if (rule.core.size() != centers.size())
      throw Error("addConvexParts: " + std::to_string(rule.core.size()) + " core flags for " +
                  std::to_string(centers.size()) + " voxels");
    if (!(std::isfinite(rule.support_reach) && rule.support_reach >= 0.0))
      throw Error::inParameter("support_reach", "must be finite and >= 0");
  }

  /// parts: each part's voxels as indices into the centres.
  std::vector<char> strays(const std::vector<std::vector<std::size_t>>& parts,
                           const std::vector<Eigen::Vector3d>& centers) const {
    std::vector<char> out(parts.size(), 0);
    if (parts.size() < 2) return out;
    std::size_t kept = parts.size();
    for (std::size_t k = 0; k < parts.size(); ++k) {
      const auto& part = parts[k];
      if (part.size() > rule_.max_voxels) continue;
      const auto core = std::count_if(part.begin(), part.end(), [&](std::size_t i) { return rule_.core[i] != 0; });
      if (std::size_t(core) > rule_.max_core_voxels) continue;
      if (std::any_of(part.begin(), part.end(), [&](std::size_t i) { return supported(centers[i]); })) continue;
      out[k] = 1;
      --kept;
    }
    if (kept == 0) std::fill(out.begin(), out.end(), 0);  // never the whole obstacle
    return out;
  }

 private:
  bool supported(const Eigen::Vector3d& p) const {
    if (rule_.support.empty()) return false;
    std::uint32_t nearest = 0;
    double squared = 0.0;
    const double query[3] = {p.x(), p.y(), p.z()};
    tree_.knnSearch(query, 1, &nearest, &squared);
    return squared <= reach2_;
  }

  const StrayParts& rule_;
  double reach2_;
  core::PointsAdaptor cloud_;
  core::PointKdTree<3> tree_;
};

/// One part of a cluster wrapped as a whole obstacle is (hull, footprint, volume, ...), with its
/// check's bound and flags, and the observed-free voxel centres (`free`, sorted by x) inside its hull,
/// and of those the ones beyond its surface band (none of its voxels among their 26 neighbours).
/// `origin`: the cluster lattice's, which the check's hull is on.
ObstaclePart wrapPart(int id, const std::vector<std::size_t>& members, const Check& check,
                      const Eigen::Vector3d& origin, const std::vector<Eigen::Vector3d>& centers,
                      const std::vector<std::uint32_t>& weights, double voxel_size,
                      const std::vector<Eigen::Vector3d>& free) {
  const Obstacle whole = detail::wrapCluster(id, members, centers, weights, voxel_size);
  ObstaclePart part;
  part.voxel_count = whole.voxel_count;
  part.point_weight = whole.point_weight;
  part.aabb_min = whole.aabb_min;
  part.aabb_max = whole.aabb_max;
  part.centroid = whole.centroid;
  part.volume = whole.volume;
  part.hull = whole.hull;
  part.footprint = whole.footprint;
  part.concavity_bound = std::sqrt(double(check.worst_d2)) * voxel_size;
  part.flat = check.flat;
  part.filled = check.filled;
  part.faces = check.faces;
  const auto cellOf = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d c = ((p - origin) / voxel_size).array().round();
    return std::array<std::int64_t, 3>{std::int64_t(c.x()), std::int64_t(c.y()), std::int64_t(c.z())};
  };
  std::set<std::array<std::int64_t, 3>> own;
  for (const auto i : members) own.insert(cellOf(centers[i]));
  const auto nearOwn = [&](const Eigen::Vector3d& p) {
    const auto c = cellOf(p);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz)
          if (own.count({c[0] + dx, c[1] + dy, c[2] + dz})) return true;
    return false;
  };
  const auto first = std::lower_bound(free.begin(), free.end(), part.aabb_min.x(),
                                      [](const Eigen::Vector3d& p, double x) { return p.x() < x; });
  for (auto it = first; it != free.end() && it->x() <= part.aabb_max.x(); ++it) {
    if ((it->array() < part.aabb_min.array()).any() || (it->array() > part.aabb_max.array()).any()) continue;
    if (!inside(check.hull, (*it - origin) / voxel_size)) continue;
    ++part.free_voxels_inside;
    if (!nearOwn(*it)) ++part.free_voxels_off_surface;
  }
  return part;
}

/// growSparseEdges, unless the grown hull would contain a keyframe that the part's own hull keeps
/// out (a camera was there): then the part stays as its check left it. Returns the growth.
double growWithoutKeyframes(ObstaclePart& part, double voxel_size, const SparseEdges& params,
                            const std::vector<Eigen::Vector3d>& keyframes) {
  const ObstaclePart before = part;
  const double grown = growSparseEdges(part, voxel_size, params);
  if (!(grown > 0.0)) return grown;
  for (const auto& k : keyframes) {
    if ((k.array() < part.aabb_min.array()).any() || (k.array() > part.aabb_max.array()).any()) continue;
    if (hullContains(part.hull, k) && !hullContains(before.hull, k)) {
      part = before;
      return 0.0;
    }
  }
  return grown;
}

}  // namespace

ConvexPartsSummary addConvexParts(std::vector<Obstacle>& obstacles, const std::vector<Eigen::Vector3d>& centers,
                                  const std::vector<std::uint32_t>& weights, const std::vector<std::int32_t>& labels,
                                  double voxel_size, const ConvexPartsParams& params, const KnownFreeSpace& known,
                                  const StrayParts* strays) {
  const double t = resolveConcavity(params, voxel_size);
  const double g = resolveFlatGap(params, t);
  checkFloor(params);
  if (labels.size() != centers.size())
    throw Error("addConvexParts: " + std::to_string(labels.size()) + " labels for " + std::to_string(centers.size()) +
                " voxels");
  if (!weights.empty() && weights.size() != centers.size())
    throw Error("addConvexParts: " + std::to_string(weights.size()) + " weights for " + std::to_string(centers.size()) +
                " voxels");
  std::map<std::int32_t, std::vector<std::size_t>> clusters;
  for (std::size_t i = 0; i < centers.size(); ++i)
    if (labels[i] >= 0) clusters[labels[i]].push_back(i);
  for (const auto& o : obstacles)
    if (!clusters.count(o.id))
      throw Error("addConvexParts: obstacle id " + std::to_string(o.id) + " is no label of the voxels");
  // Free voxel centres sorted by x, for a range per part.
  std::vector<Eigen::Vector3d> free = known.free_voxels;
  std::sort(free.begin(), free.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
  });
  std::vector<std::size_t> keyframes_in_voxels(obstacles.size(), 0), flat_parts(obstacles.size(), 0),
      face_parts(obstacles.size(), 0);
  std::vector<double> flat_gaps(obstacles.size(), g);
  const std::optional<StrayRule> stray_rule =
      strays ? std::optional<StrayRule>(std::in_place, *strays, centers, t) : std::nullopt;
  std::vector<std::vector<std::size_t>> stray_voxels(obstacles.size());
  std::vector<std::size_t> stray_parts(obstacles.size(), 0), grown_parts(obstacles.size(), 0);
  std::vector<double> grown_most(obstacles.size(), 0.0);
  tbb::parallel_for(std::size_t(0), obstacles.size(), [&](std::size_t o) {
    Obstacle& obstacle = obstacles[o];
    const std::vector<std::size_t>& members = clusters.at(obstacle.id);
    std::vector<Eigen::Vector3d> local;
    local.reserve(members.size());
    for (const auto i : members) local.push_back(centers[i]);
    const SplitResult result = splitCluster(local, voxel_size, t, params, known.keyframes);
    flat_gaps[o] = result.flat_gap;
    obstacle.parts.clear();
    std::vector<std::vector<std::size_t>> globals;
    globals.reserve(result.parts.size());
    for (const auto& part : result.parts) {
      std::vector<std::size_t>& global = globals.emplace_back();
      global.reserve(part.first.size());
      for (const auto i : part.first) global.push_back(members[i]);
    }
    const std::vector<char> dropped =
        stray_rule ? stray_rule->strays(globals, centers) : std::vector<char>(globals.size(), 0);
    for (std::size_t k = 0; k < result.parts.size(); ++k) {
      const auto& check = result.parts[k].second;
      const std::vector<std::size_t>& global = globals[k];
      if (dropped[k]) {
        ++stray_parts[o];
        stray_voxels[o].insert(stray_voxels[o].end(), global.begin(), global.end());
        continue;
      }
      if (check.flat) ++flat_parts[o];
      if (check.faces) ++face_parts[o];
      keyframes_in_voxels[o] += check.keyframes_in_voxels;
      obstacle.parts.push_back(
          wrapPart(obstacle.id, global, check, result.lattice.origin, centers, weights, voxel_size, free));
      if (params.sparse_edges) {
        const double grown =
            growWithoutKeyframes(obstacle.parts.back(), voxel_size, *params.sparse_edges, known.keyframes);
        grown_parts[o] += grown > 0.0 ? 1 : 0;
        grown_most[o] = std::max(grown_most[o], grown);
      }
    }
    // The whole obstacle again, from the voxels it keeps.
    if (stray_parts[o] > 0) {
      std::sort(stray_voxels[o].begin(), stray_voxels[o].end());
      std::vector<std::size_t> kept;
      std::set_difference(members.begin(), members.end(), stray_voxels[o].begin(), stray_voxels[o].end(),
                          std::back_inserter(kept));
      std::vector<ObstaclePart> parts = std::move(obstacle.parts);
      obstacle = detail::wrapCluster(obstacle.id, kept, centers, weights, voxel_size);
      obstacle.parts = std::move(parts);
    }
  });
  ConvexPartsSummary summary;
  summary.concavity = t;
  summary.flat_gap = g;
  summary.flat_gap_max = g;
  for (const double used : flat_gaps) summary.flat_gap_max = std::max(summary.flat_gap_max, used);
  std::vector<std::pair<std::size_t, int>> strays_of;  // stray voxel, the obstacle it left
  for (std::size_t o = 0; o < obstacles.size(); ++o) {
    const auto& obstacle = obstacles[o];
    summary.parts += obstacle.parts.size();
    summary.hull_volume_before += obstacle.volume;
    summary.voxel_volume += double(obstacle.voxel_count) * voxel_size * voxel_size * voxel_size;
    summary.keyframes_in_voxels += keyframes_in_voxels[o];
    summary.flat_parts += flat_parts[o];
    summary.face_parts += face_parts[o];
    summary.stray_parts += stray_parts[o];
    summary.sparse_edge_parts += grown_parts[o];
    summary.sparse_edge_growth_max = std::max(summary.sparse_edge_growth_max, grown_most[o]);
    for (const std::size_t i : stray_voxels[o]) strays_of.emplace_back(i, obstacle.id);
    for (const auto& part : obstacle.parts) {
      summary.hull_volume_after += part.volume;
      summary.free_voxels_inside += part.free_voxels_inside;
      summary.free_voxels_off_surface += part.free_voxels_off_surface;
    }
  }
  std::sort(strays_of.begin(), strays_of.end());
  for (const auto& [i, id] : strays_of) {
    summary.stray_voxels.push_back(i);
    summary.stray_obstacles.push_back(id);
  }
  return summary;
}

}  // namespace hullmap::hulls
