#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace hullmap::clustering {

/// Distance used by DBSCAN: full 3D, or the ground plane (x, y) after the frame change (z up).
enum class Metric { kXyz, kXy };
Metric parseMetric(const std::string& text);  ///< "xyz" or "xy"; throws hullmap::Error naming --metric
std::string toString(Metric metric);

/// DBSCAN settings. Defaults are the seed report's reference case.
struct DbscanParams {
  double eps = 0.1;  ///< neighbourhood radius, map units; N_eps(p) = {q : d(p,q) <= eps}
  int min_pts = 10;  ///< core when the weight of N_eps(p), p included, is >= min_pts
  Metric metric = Metric::kXyz;
};

/// Label of a point that is in no cluster.
inline constexpr std::int32_t kNoise = -1;

struct DbscanResult {
  std::vector<std::int32_t> labels;        ///< per point: kNoise or 0..k-1, numbered by first point
  std::vector<std::uint8_t> core;          ///< per point: 1 when core
  std::vector<std::size_t> cluster_sizes;  ///< points per cluster (not weights), index = label
  std::size_t noise = 0;                   ///< points labelled kNoise
  /// Core distances of the sampled points, sorted descending; filled only by the dbscan() overload
  /// taking a KDistanceRequest (see there).
  std::vector<double> k_distance_curve;
};

/// Asks dbscan() for the k-distance curve as well, from its own grid.
struct KDistanceRequest {
  /// Points whose distance is computed: those kDistanceSample(n, max_samples) picks, evenly spread over
  /// the input; 0: every point.
  std::size_t max_samples = 0;
};

/// Exact DBSCAN (Ester et al. 1996) with a grid of cells of side eps/sqrt(d): linear memory, parallel
/// on all cores (TBB), results independent of the thread count.
///
/// Semantics, exactly:
/// - q is a neighbour of p when the squared distance, computed in double as dx*dx + dy*dy (+ dz*dz),
///   is <= eps*eps: points at exactly eps are neighbours. p is its own neighbour.
/// - p is core when the summed weight of its neighbours is >= min_pts.
/// - Clusters are the connected components of core points under "neighbour".
/// - A non-core point with a core neighbour is a border point. It joins the cluster of its nearest
///   core neighbour; among equally near ones, the one that comes first in the input.
/// - Everything else is noise (kNoise).
/// - Clusters are numbered 0..k-1 in the order of their first point in the input, core or border.
/// The result depends only on the input, never on the number of threads.
///
/// `weights` empty means weight 1 per point; otherwise one positive weight per point (a voxel's map
/// point count). Throws hullmap::Error on eps <= 0, min_pts < 1, non-finite points, points so far
/// away that their grid cell does not fit in 63 bits, more than 2^32 - 2 points, a zero weight or a
/// size mismatch. Thread-safe (no shared state); uses the TBB arena of the caller.
DbscanResult dbscan(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
                    const DbscanParams& params);

/// dbscan() plus the k-distance curve of a sample, answered on DBSCAN's own grid (no second index):
/// result.k_distance_curve holds, sorted descending, each sampled point's core distance, the smallest
/// r such that the points within r (squared distance <= r*r, the point itself included) weigh at
/// least min_pts. With unit weights that is the distance to the k-th nearest other point, k =
/// min_pts - 1: the same values as kDistanceCurve(points, min_pts, metric, request.max_samples), to the
/// last bit. Empty when all points together weigh less than min_pts; all zeros when min_pts is 1.
///
/// Each query searches the 3^d cells around its own (cells of side eps/sqrt(d)), then, only when its
/// k-th neighbour may lie farther out, groups of 16^d cells nearest first (exact: whole cells and
/// groups are skipped by their bounding boxes). The cost is about that of the queries alone when most
/// sampled points are core or border points; it grows with the points per cell when eps is far larger
/// than the point spacing. The labels are those of dbscan() with the same arguments.
DbscanResult dbscan(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
                    const DbscanParams& params, const KDistanceRequest& k_distance);

/// Distance to the k-th nearest neighbour (k = min_pts - 1, the point itself not counted; duplicates
/// count) of each point under `metric`, sorted descending: the k-distance curve. Weights are not used.
/// min_pts <= 1 gives all zeros; with fewer than min_pts points the curve is empty.
///
/// With `max_samples` > 0 and more points than that, the curve holds the exact k-distances (against
/// all points) of the max_samples points kDistanceSample picks, evenly spread over the input: a
/// sample of the full curve, for an eps suggestion on millions of points (`hullmap cluster` samples
/// kEpsSuggestionSamples). 0: every point.
///
/// nanoflann's k-d tree, in parallel (TBB); the distances are those of the brute-force definition
/// (squared differences summed per axis in axis order, then the square root). Throws hullmap::Error
/// on min_pts < 1 or non-finite points.
std::vector<double> kDistanceCurve(const std::vector<Eigen::Vector3d>& points, int min_pts, Metric metric,
                                   std::size_t max_samples = 0);

/// Points whose k-distance a sampled curve holds: floor(j * n / count) for j < count, count =
/// min(n, max_samples) (all n when max_samples is 0), ascending.
std::vector<std::uint32_t> kDistanceSample(std::size_t n, std::size_t max_samples);

/// Sample size of `hullmap cluster`'s eps suggestion (answered on DBSCAN's grid, see dbscan() with a
/// KDistanceRequest). Why 2048: docs/DESIGN_NOTES.md, "dbscan.hpp: kEpsSuggestionSamples".
inline constexpr std::size_t kEpsSuggestionSamples = 2048;

/// Suggested eps: the knee of the k-distance curve, found by this rule:
/// 1. drop the largest 1% of the values (at least one value when there are 100 or more), so that gross
///    outliers hundreds of kilometres away do not flatten the curve;
/// 2. scale the remaining curve to [0,1] on both axes (index and distance);
/// 3. the knee is the value farthest below the chord from the first to the last remaining value.
/// Returns 0 for an empty curve, and the single value when the remaining curve is flat or too short.
double suggestEps(const std::vector<double>& k_distance_curve);

}  // namespace hullmap::clustering
