#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <octomap/OcTree.h>

#include "hullmap/io/point_cloud.hpp"
#include "hullmap/io/readers.hpp"

namespace hullmap::mapper {

/// OctoMap's sensor model (probabilities; the tree stores their log-odds). Defaults are octomap's
/// own (OcTree's constructor): --hit, --miss, --clamp-min, --clamp-max, --occupancy-threshold.
struct SensorModel {
  double hit = 0.7;
  double miss = 0.4;
  double clamp_min = 0.1192;
  double clamp_max = 0.971;
  double occupancy_threshold = 0.5;
};

struct OctreeParams {
  double resolution = 0.05;  ///< leaf size, map units
  SensorModel sensor;
  double max_range = -1.0;  ///< ray length bound for free space; < 0: unbounded
};

/// An occupied leaf voxel at the finest resolution, in the map frame.
struct OccupiedVoxel {
  Eigen::Vector3d center;
  std::uint32_t weight = 1;  ///< map points that fell in it (1 for voxels read from a .bt)
  double log_odds = 0.0;
};

/// An OctoMap OcTree (z-up map frame, map units) plus, per leaf key, how many map points fell in it.
/// Not thread-safe for writing; const methods may be called concurrently.
class OccupancyMap {
 public:
  explicit OccupancyMap(const OctreeParams& params);

  octomap::OcTree& tree() { return *tree_; }
  const octomap::OcTree& tree() const { return *tree_; }
  double resolution() const { return tree_->getResolution(); }

  /// Map points per leaf key (only keys where points fell).
  const std::unordered_map<octomap::OcTreeKey, std::uint32_t, octomap::OcTreeKey::KeyHash>& pointCounts() const {
    return point_counts_;
  }
  std::unordered_map<octomap::OcTreeKey, std::uint32_t, octomap::OcTreeKey::KeyHash>& pointCounts() {
    return point_counts_;
  }

  /// Occupied leaves at the finest depth (pruned inner leaves expanded), sorted by key so the
  /// order is deterministic. Weight from pointCounts(), or 1 where no count is known.
  /// Throws hullmap::Error when they would be more than 2^25 (a pruned leaf near the root of a
  /// corrupt .bt stands for up to 2^45).
  std::vector<OccupiedVoxel> occupiedVoxels() const;

 private:
  std::unique_ptr<octomap::OcTree> tree_;
  std::unordered_map<octomap::OcTreeKey, std::uint32_t, octomap::OcTreeKey::KeyHash> point_counts_;
};

/// True when octomap can address `p` at this resolution (inside +-2^15 leaves of the origin).
bool addressable(const octomap::OcTree& tree, const io::Point& p);

/// Builds the map from points alone: each point an occupied endpoint, exactly as calling octomap's
/// updateNode(point3d(p), true) once per point (float coordinates, so several points in one voxel
/// are several hit updates, clamped as octomap clamps). Points the tree cannot address (farther than
/// 2^15 leaves from the origin: ORB-SLAM's gross outliers) are dropped and counted in `stats`
/// under "out_of_octree". Uses all cores (TBB). The same map as PointMapBuilder given the points in
/// any batches.
OccupancyMap buildFromPoints(const io::Points& points, const OctreeParams& params, io::InputStats& stats);

/// Builds the points-only map of buildFromPoints from points given in batches, holding per voxel
/// met, not per point: add() turns a batch's points into voxel keys (16 bytes a point) and merges
/// them into one (voxel, point count) entry per voxel (16 bytes a voxel, twice that during a merge)
/// once they are as many as the voxels so far (at least 16384); finish() applies the entries to the
/// tree in one pass. Every update is a hit, so the order of the points and how they are cut into
/// batches do not matter: finish() gives the tree and point counts of buildFromPoints on all
/// batches concatenated, the tree of octomap's updateNode(point3d(p), true) once per point.
/// Not thread-safe; add() uses all cores (TBB). A moved-from builder may only be destroyed or
/// assigned to.
class PointMapBuilder {
 public:
  /// Throws hullmap::Error naming the parameter at fault, as OccupancyMap's constructor.
  explicit PointMapBuilder(const OctreeParams& params);
  ~PointMapBuilder();
  PointMapBuilder(PointMapBuilder&&) noexcept;
  PointMapBuilder& operator=(PointMapBuilder&&) noexcept;

  /// Adds one batch of points (map frame, map units). Points the tree cannot address are dropped
  /// and counted in `stats` under "out_of_octree", as in buildFromPoints.
  void add(const io::Points& points, io::InputStats& stats);

  /// The map of every point added so far; the builder starts over empty.
  OccupancyMap finish();

 private:
  friend OccupancyMap buildFromPoints(const io::Points& points, const OctreeParams& params, io::InputStats& stats);
  struct State;
  std::unique_ptr<State> state_;
};

/// Builds the map with free space. Keyframes must already be in the map frame.
///
/// Keyframe rule: a point is taken as seen from the nearest keyframe position (Euclidean, ties to
/// the earlier keyframe) among those whose viewing direction (camera +z rotated by the keyframe's
/// orientation) has a positive dot product with the direction to the point; when no keyframe faces
/// it, from the nearest keyframe. A uniform grid over the keyframe positions finds the same
/// keyframe as this brute-force rule, fast for millions of points.
///
/// The points of each keyframe (in input order) then form one scan inserted with insertScan from
/// that keyframe's position, bounded by params.max_range, keyframes in trajectory order: the same
/// tree as octomap's insertPointCloud per group. Unaddressable points are dropped and counted under
/// "out_of_octree" before grouping (they cast no ray). Throws hullmap::Error without keyframes.
OccupancyMap buildWithTrajectory(const io::Points& points, const std::vector<io::Keyframe>& keyframes,
                                 const OctreeParams& params, io::InputStats& stats);

/// Builds the map of one scan: `points` (map frame) inserted with insertScan from `origin`, rays
/// bounded by params.max_range, and each point counted in its voxel. Points the tree cannot
/// address are dropped first and counted under "out_of_octree" (they cast no ray). Keys are
/// computed as insertScan computes them (float coordinates, octomap's coordToKey).
OccupancyMap buildFromScan(const io::Points& points, const io::Point& origin, const OctreeParams& params,
                           io::InputStats& stats);

/// Inserts one scan from `origin` exactly as octomap's insertPointCloud(points, origin, max_range)
/// would with its defaults (lazy_eval and discretize off): same leaves, same log-odds, same pruning.
/// Faster: ray keys cast in parallel (TBB) into per-thread sets, merged without a lock (occupied
/// wins over free), then applied in one depth-first pass in octree order. Points and origin are
/// converted to float as octomap's point3d. Unlike octomap, rays longer than 100000 voxels are
/// safe. With a bounding box or change detection set on `tree`, octomap's own insertPointCloud runs.
void insertScan(octomap::OcTree& tree, const io::Points& points, const io::Point& origin, double max_range);

/// Reads a .bt or .ot map (recognised by its header). The node stream is checked before octomap
/// reads it, and octomap's result is checked: a missing, truncated, corrupt or non-OctoMap file is
/// an Error naming it. A .bt holds no point counts (and only maximum-likelihood log-odds): its
/// occupied voxels have weight 1. A .bt tree gets octomap's default sensor model.
///
/// stderr: neither readMap nor writeMap prints anything or touches the process's stderr. (Debian's
/// liboctomap prints progress from writeBinary/writeBinaryConst; writeMap writes the .bt header
/// itself and calls octomap's writeBinaryNode, which prints nothing, giving the same bytes.)
/// Thread-safe for distinct maps and paths.
OccupancyMap readMap(const std::string& path);

/// Writes the tree as .bt (binary, octomap's writeBinaryConst: maximum likelihood, no counts) or
/// .ot (full log-odds) by extension, atomically (temporary file + rename). Other extensions are an
/// Error naming the path. Mutes fd 2 around octomap's call as readMap does (see there).
void writeMap(const OccupancyMap& map, const std::string& path);

/// Summary for `hullmap info`: resolution, metric bounds of the tree (getMetricMin/Max, zero when
/// empty), leaf counts (pruned leaves count once), nodes and octomap's memoryUsage() in bytes.
struct MapInfo {
  double resolution = 0.0;
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
  std::size_t occupied_leaves = 0;
  std::size_t free_leaves = 0;
  std::size_t nodes = 0;
  std::size_t memory_bytes = 0;
};
MapInfo describe(const octomap::OcTree& tree);

}  // namespace hullmap::mapper
