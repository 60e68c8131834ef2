#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <octomap/OcTree.h>

#include "hullmap/mapper/point_cloud.hpp"
#include "hullmap/mapper/readers.hpp"

namespace hullmap::mapper {

/// OctoMap's sensor model. Defaults are octomap's own (OcTree's constructor).
struct SensorModel {
  double hit = 0.7;
  double miss = 0.4;
  double clamp_min = 0.1192;
  double clamp_max = 0.971;
  double occupancy_threshold = 0.5;
};

struct OctreeParams {
  double resolution = 0.05;   ///< leaf size, map units
  SensorModel sensor;
  double max_range = -1.0;    ///< ray length bound for free space; < 0: unbounded
};

/// An occupied leaf voxel at the finest resolution, in the map frame.
struct OccupiedVoxel {
  Eigen::Vector3d center;
  std::uint32_t weight = 1;   ///< map points that fell in it (1 for voxels read from a .bt)
  double log_odds = 0.0;
};

/// An OctoMap OcTree plus, per occupied leaf, how many map points fell in it.
class OccupancyMap {
 public:
  explicit OccupancyMap(const OctreeParams& params);

  octomap::OcTree& tree() { return *tree_; }
  const octomap::OcTree& tree() const { return *tree_; }
  double resolution() const { return tree_->getResolution(); }

  /// Map points per leaf key (only keys where points fell).
  const std::unordered_map<octomap::OcTreeKey, std::uint32_t, octomap::OcTreeKey::KeyHash>&
  pointCounts() const { return point_counts_; }
  std::unordered_map<octomap::OcTreeKey, std::uint32_t, octomap::OcTreeKey::KeyHash>&
  pointCounts() { return point_counts_; }

  /// Occupied leaves at the finest depth (pruned inner leaves expanded), sorted by key so the
  /// order is deterministic. Weight from pointCounts(), or 1 where no count is known.
  std::vector<OccupiedVoxel> occupiedVoxels() const;

 private:
  std::unique_ptr<octomap::OcTree> tree_;
  std::unordered_map<octomap::OcTreeKey, std::uint32_t, octomap::OcTreeKey::KeyHash> point_counts_;
};

/// True when octomap can address `p` at this resolution (inside +-2^15 leaves of the origin).
bool addressable(const octomap::OcTree& tree, const Point& p);

/// Builds the map from points alone: each point an occupied endpoint (updateNode(p, true)).
/// Points the tree cannot address are dropped and counted in `stats` under "out_of_octree".
OccupancyMap buildFromPoints(const Points& points, const OctreeParams& params, InputStats& stats);

/// Builds the map with free space: each point is ray-cast from the keyframe it was most likely
/// seen from (see docs in the README, "Keyframe rule"), bounded by params.max_range.
OccupancyMap buildWithTrajectory(const Points& points, const std::vector<Keyframe>& keyframes,
                                 const OctreeParams& params, InputStats& stats);

/// Inserts one scan from `origin` exactly as octomap's insertPointCloud(points, origin, max_range)
/// would (same leaves, same log-odds), but faster: parallel ray keys, lock-free deduplication.
void insertScan(octomap::OcTree& tree, const Points& points, const Point& origin,
                double max_range);

/// Reads a .bt (or .ot) map. Checks readBinary's result: a corrupt file is an Error naming it.
OccupancyMap readMap(const std::string& path);

/// Writes tree as .bt (binary, octomap's writeBinary) or .ot (full) by extension, atomically
/// (temporary file + rename).
void writeMap(const OccupancyMap& map, const std::string& path);

/// Summary for `hullmap info`.
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
