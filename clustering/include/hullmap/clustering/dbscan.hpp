#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace hullmap::clustering {

/// Distance used by DBSCAN: full 3D, or the ground plane (x, y) after the frame change.
enum class Metric { kXyz, kXy };
Metric parseMetric(const std::string& text);  ///< "xyz" or "xy"; throws hullmap::Error naming --metric
std::string toString(Metric metric);

/// DBSCAN settings. Defaults are the seed report's reference case.
struct DbscanParams {
  double eps = 0.1;        ///< neighbourhood radius, map units; N_eps(p) = {q : d(p,q) <= eps}
  int min_pts = 10;        ///< core when the weight of N_eps(p), p included, is >= min_pts
  Metric metric = Metric::kXyz;
};

/// Label of a point that is in no cluster.
inline constexpr std::int32_t kNoise = -1;

struct DbscanResult {
  std::vector<std::int32_t> labels;       ///< per point: kNoise or 0..k-1, numbered by first point
  std::vector<std::uint8_t> core;         ///< per point: 1 when core
  std::vector<std::size_t> cluster_sizes; ///< points per cluster (not weights), index = label
  std::size_t noise = 0;                  ///< points labelled kNoise
};

/// Exact DBSCAN (Ester et al. 1996) with a grid of cells of side eps/sqrt(d): linear memory, parallel
/// on all cores (TBB), results independent of the thread count.
/// `weights` empty means weight 1 per point; otherwise one positive weight per point (a voxel's map
/// point count). Throws hullmap::Error on eps <= 0, min_pts < 1, non-finite points or a size mismatch.
DbscanResult dbscan(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
                    const DbscanParams& params);

/// Distance to the k-th nearest neighbour (k = min_pts - 1, the point itself not counted) of each point,
/// sorted descending: the k-distance curve.
std::vector<double> kDistanceCurve(const std::vector<Eigen::Vector3d>& points, int min_pts, Metric metric);

/// Suggested eps: the knee of the k-distance curve (point of maximum distance to the chord from
/// the first to the last value). See README "Choosing eps".
double suggestEps(const std::vector<double>& k_distance_curve);

}  // namespace hullmap::clustering
