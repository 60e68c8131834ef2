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

/// Open-addressing set of packed keys (linear probing, load <= 1/2). Not thread-safe.
class PackedKeySet {
 public:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  void insert(std::uint64_t key);
  bool contains(std::uint64_t key) const;
  std::size_t size() const { return size_; }
  const std::vector<std::uint64_t>& slots() const { return slots_; }

 private:
  std::size_t slot(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  void grow();
  std::vector<std::uint64_t> slots_;
  std::size_t size_ = 0;
  unsigned shift_ = 64;
};

/// octomap's coordToKeyChecked and computeRayKeys, same arithmetic, writing into a PackedKeySet.
class KeyCaster {
 public:
  explicit KeyCaster(const octomap::OcTree& tree);
  bool coordToKeyChecked(double coordinate, int& key) const;
  bool coordToKeyChecked(const octomap::point3d& p, int key[3]) const;
  /// The free keys of the ray origin -> end (end excluded). False when either end is not addressable.
  bool castRay(const octomap::point3d& origin, const octomap::point3d& end, PackedKeySet& out) const;

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
