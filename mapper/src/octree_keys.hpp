#pragma once
// Internals of insertScan shared with the benchmarks: ray casting into key sets, Morton order,
// the batched tree update. Not installed.

#include <cstdint>
#include <vector>

#include <octomap/OcTree.h>

#include "hullmap/mapper/point_cloud.hpp"

namespace hullmap::mapper::detail {

/// Key (k0, k1, k2) packed as k0 | k1 << 16 | k2 << 32.
inline std::uint64_t pack(const int key[3]) {
  return static_cast<std::uint64_t>(key[0]) | static_cast<std::uint64_t>(key[1]) << 16 |
         static_cast<std::uint64_t>(key[2]) << 32;
}

/// Interleaves a packed key so that bits 3l..3l+2 are octomap's child index at level l
/// (computeChildIdx): sorting by it is octree depth-first order.
std::uint64_t mortonCode(std::uint64_t packed);
octomap::OcTreeKey mortonKey(std::uint64_t morton);

/// Free and occupied voxels of one thread's rays: 8x8x8 bricks of bits (Morton order inside a
/// brick). Bricks inside an optional dense box (brick coordinates) are found by arithmetic, others
/// through an open-addressing index. Consecutive ray keys mostly stay in one brick, so most marks
/// are a bit set in a cached line. Not thread-safe.
class BrickSet {
 public:
  struct Brick {
    std::uint64_t free[8] = {};
    std::uint64_t occupied[8] = {};
    bool empty() const {
      std::uint64_t any = 0;
      for (int w = 0; w < 8; ++w) any |= free[w] | occupied[w];
      return any == 0;
    }
  };
  BrickSet() = default;
  /// Bricks with lo <= coordinate < lo + dims (per axis, brick = key >> 3) are stored densely.
  BrickSet(const int lo[3], const int dims[3]);

  void mark(const int key[3], bool occupied) {
    const std::uint64_t coord = static_cast<std::uint64_t>(key[0] >> 3) |
                                static_cast<std::uint64_t>(key[1] >> 3) << 13 |
                                static_cast<std::uint64_t>(key[2] >> 3) << 26;
    if (coord != last_coord_) {
      last_index_ = find(coord);
      last_coord_ = coord;
    }
    const unsigned bit = kSpread[key[0] & 7] | kSpread[key[1] & 7] << 1 | kSpread[key[2] & 7] << 2;
    Brick& b = bricks_[last_index_];
    (occupied ? b.occupied : b.free)[bit >> 6] |= std::uint64_t{1} << (bit & 63);
  }
  std::size_t denseCount() const { return dense_count_; }
  std::vector<Brick>& bricks() { return bricks_; }
  const std::vector<Brick>& bricks() const { return bricks_; }
  /// Brick coordinate (x | y << 13 | z << 26) of bricks()[i].
  std::uint64_t coordOf(std::size_t i) const;

 private:
  static constexpr unsigned kSpread[8] = {0, 1, 8, 9, 64, 65, 72, 73};
  std::uint32_t find(std::uint64_t coord);
  int lo_[3] = {0, 0, 0};
  int dims_[3] = {0, 0, 0};
  std::size_t dense_count_ = 0;
  std::vector<std::uint64_t> slots_;      // coord + 1, 0 = empty
  std::vector<std::uint32_t> slot_index_;
  std::vector<Brick> bricks_;             // dense box first, then the others
  std::vector<std::uint64_t> coords_;     // of the bricks after the dense box
  std::uint64_t last_coord_ = ~std::uint64_t{0};
  std::uint32_t last_index_ = 0;
  unsigned shift_ = 64;
};

/// octomap's coordToKeyChecked and computeRayKeys, same arithmetic, writing into a BrickSet.
class KeyCaster {
 public:
  explicit KeyCaster(const octomap::OcTree& tree);
  bool coordToKeyChecked(double coordinate, int& key) const;
  bool coordToKeyChecked(const octomap::point3d& p, int key[3]) const;
  /// The free keys of the ray origin -> end (end excluded). False when either end is not addressable.
  bool castRay(const octomap::point3d& origin, const octomap::point3d& end, BrickSet& out) const;

 private:
  double resolution_;
  double resolution_factor_;
  int max_val_;
};

/// `count` updates of one voxel: code = Morton key << 1 | occupied.
struct VoxelUpdate {
  std::uint64_t code = 0;
  std::uint32_t count = 1;
};

/// Sorts by code (octree depth-first order), LSD radix.
void sortUpdates(std::vector<VoxelUpdate>& updates);

/// One scan's updates, deduplicated (occupied wins, as octomap's computeUpdate), sorted, count 1.
std::vector<VoxelUpdate> computeScanUpdate(const octomap::OcTree& tree, const Points& points,
                                           const Point& origin, double max_range);

/// Applies sorted updates (one entry per voxel) as calling octomap's updateNode(key, occupied)
/// `count` times per entry would, in any order. Reorders and shrinks nothing the caller keeps.
void applyUpdates(octomap::OcTree& tree, std::vector<VoxelUpdate>& updates);

}  // namespace hullmap::mapper::detail
