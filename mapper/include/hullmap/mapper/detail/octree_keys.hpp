#pragma once
// Internals of insertScan shared with the tests and benchmarks: ray casting into key sets, Morton
// order, the batched tree update. Installed with the other headers, but detail: no stable API.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <octomap/OcTree.h>

#include "hullmap/io/point_cloud.hpp"

namespace hullmap::mapper::detail {

/// Key (k0, k1, k2) packed as k0 | k1 << 16 | k2 << 32.
inline std::uint64_t pack(const int key[3]) {
  return static_cast<std::uint64_t>(key[0]) | static_cast<std::uint64_t>(key[1]) << 16 |
         static_cast<std::uint64_t>(key[2]) << 32;
}

/// Set bits (SWAR: x86-64's baseline has no popcnt instruction).
inline std::size_t bitCount(std::uint64_t v) {
  v = v - ((v >> 1) & 0x5555555555555555ull);
  v = (v & 0x3333333333333333ull) + ((v >> 2) & 0x3333333333333333ull);
  v = (v + (v >> 4)) & 0x0F0F0F0F0F0F0F0Full;
  return static_cast<std::size_t>((v * 0x0101010101010101ull) >> 56);
}

/// Interleaves a packed key so that bits 3l..3l+2 are octomap's child index at level l
/// (computeChildIdx): sorting by it is octree depth-first order.
std::uint64_t mortonCode(std::uint64_t packed);
octomap::OcTreeKey mortonKey(std::uint64_t morton);

/// Free and occupied voxels of one thread's rays: 8x8x8 bricks of bits (Morton order inside a
/// brick, 8 words of 64 bits), allocated when first marked, one array of words for free voxels
/// and one for occupied. Bricks inside an optional box (brick coordinates) are found through a
/// grid of brick indices, others through an open-addressing index. Not thread-safe.
class BrickSet {
 public:
  static constexpr std::size_t kWords = 8;

  BrickSet() = default;
  /// Bricks with lo <= coordinate < lo + dims (per axis, brick = key >> 3) are found through the
  /// grid; `allocate_grid`: all of them allocated up front, in grid order.
  BrickSet(const int lo[3], const int dims[3], bool allocate_grid);

  void mark(const int key[3], bool occupied) {
    const std::uint64_t coord = static_cast<std::uint64_t>(key[0] >> 3) |
                                static_cast<std::uint64_t>(key[1] >> 3) << 13 |
                                static_cast<std::uint64_t>(key[2] >> 3) << 26;
    if (coord != last_coord_) {
      last_word_ = find(coord) * kWords;
      last_coord_ = coord;
    }
    const unsigned bit = kSpread[key[0] & 7] | kSpread[key[1] & 7] << 1 | kSpread[key[2] & 7] << 2;
    (occupied ? occupied_ : free_)[last_word_ + (bit >> 6)] |= std::uint64_t{1} << (bit & 63);
  }

  /// Key of the grid's low corner (brick lo * 8), per axis.
  const unsigned* gridLo() const { return grid_lo_; }
  /// Marks free the keys key_i = rel_i + gridLo()_i (16-bit wrap) of keys packed
  /// rel0 | rel1 << 16 | rel2 << 32; entries with any of bits 48-63 set are skipped.
  void markFree(const std::uint64_t* keys, std::size_t count);

  std::size_t brickCount() const { return coords_.size(); }
  bool empty(std::size_t brick) const {
    std::uint64_t any = 0;
    for (std::size_t w = 0; w < kWords; ++w) any |= free_[brick * kWords + w] | occupied_[brick * kWords + w];
    return any == 0;
  }
  const std::uint64_t* freeWords(std::size_t brick) const { return &free_[brick * kWords]; }
  const std::uint64_t* occupiedWords(std::size_t brick) const { return &occupied_[brick * kWords]; }
  /// Brick coordinate (x | y << 13 | z << 26) of brick i.
  std::uint64_t coordOf(std::size_t i) const { return coords_[i]; }

 private:
  static constexpr unsigned kSpread[8] = {0, 1, 8, 9, 64, 65, 72, 73};
  static constexpr std::uint32_t kNoBrick = ~std::uint32_t{0};
  std::uint32_t find(std::uint64_t coord);
  std::uint32_t addBrick(std::uint64_t coord);
  std::uint32_t gridBrick(std::size_t cell);
  int lo_[3] = {0, 0, 0};
  int dims_[3] = {0, 0, 0};
  unsigned grid_lo_[3] = {0, 0, 0};
  unsigned grid_extent_[3] = {0, 0, 0};      // in keys
  std::vector<std::uint32_t> grid_;          // first word of each box brick, kNoBrick: none yet
  bool grid_allocated_ = false;              // brick i is grid cell i
  std::vector<std::uint32_t> axis_code_[3];  // per axis and key - grid_lo: cell * 512 + interleaved bits
  std::vector<std::uint64_t> slots_;         // coord + 1, 0 = empty
  std::size_t hashed_ = 0;
  std::vector<std::uint32_t> slot_index_;
  std::vector<std::uint64_t> free_;  // kWords per brick
  std::vector<std::uint64_t> occupied_;
  std::vector<std::uint64_t> coords_;  // of each brick
  std::uint64_t last_coord_ = ~std::uint64_t{0};
  std::size_t last_word_ = 0;
  unsigned shift_ = 64;
};

/// octomap's coordToKeyChecked and computeRayKeys, same arithmetic, writing into a BrickSet.
class KeyCaster {
 public:
  explicit KeyCaster(const octomap::OcTree& tree)
      : resolution_(tree.getResolution()), resolution_factor_(1.0 / tree.getResolution()), max_val_(32768) {}

  bool coordToKeyChecked(double coordinate, int& key) const {
    const double scaled = std::floor(resolution_factor_ * coordinate);
    // octomap casts first; outside int's range (and for NaN) that is undefined, and never a valid key.
    if (!(scaled > -2147483648.0 && scaled < 2147483647.0)) return false;
    const int k = static_cast<int>(scaled) + max_val_;
    if (k < 0 || k >= 2 * max_val_) return false;
    key = k;
    return true;
  }
  bool coordToKeyChecked(const octomap::point3d& p, int key[3]) const {
    return coordToKeyChecked(p(0), key[0]) && coordToKeyChecked(p(1), key[1]) && coordToKeyChecked(p(2), key[2]);
  }

  /// One ray of a scan: where it ends (the point, or cut at the maximum range) and that end's key.
  struct Ray {
    octomap::point3d end;
    int key_end[3] = {0, 0, 0};
    bool casts = false;     ///< origin and end addressable: the ray clears free space
    bool occupied = false;  ///< the end is the measured point (within range): occupied
  };
  /// Marks free, in `out`, the keys octomap's computeRayKeys(origin, ray.end) returns for each
  /// ray that `casts` (the end key excluded); `key_origin` is the origin's key.
  void castRays(const octomap::point3d& origin, const int key_origin[3], const Ray* rays, std::size_t count,
                BrickSet& out) const;

 private:
  struct RayStart {
    int step[3];
    double t_max[3];
    double t_delta[3];
    double length;
  };
  /// computeRayKeys' initialisation; false when the ray has no free key (both ends in one voxel).
  bool startRay(const octomap::point3d& origin, const int key_origin[3], const octomap::point3d& end,
                const int key_end[3], RayStart& start) const;

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

/// One scan's voxels, each once: every thread's bricks, and a list of all bricks sorted in octree
/// order (a brick marked by several threads: adjacent entries, to be OR-ed). A voxel marked both
/// free and occupied is occupied (octomap's computeUpdate).
struct ScanUpdate {
  struct Entry {
    std::uint64_t code;   ///< Morton code of the brick (key >> 3 per axis)
    std::uint32_t set;    ///< index in sets
    std::uint32_t brick;  ///< index in that set
  };
  ScanUpdate() = default;
  /// The update of the voxels marked in `sets` (bricks sorted here).
  explicit ScanUpdate(std::vector<BrickSet> sets);

  std::vector<BrickSet> sets;
  std::vector<Entry> bricks;

  /// Number of voxels updated.
  std::size_t voxelCount() const;
};

/// One scan's update as insertPointCloud(points, origin, max_range) computes it (computeUpdate).
ScanUpdate computeScanUpdate(const octomap::OcTree& tree, const io::Points& points, const io::Point& origin,
                             double max_range);

/// Applies a scan's update as insertPointCloud's updateNode calls would (in any order: each voxel
/// once), in one depth-first pass.
void applyScanUpdate(octomap::OcTree& tree, const ScanUpdate& update);

/// Applies sorted updates (one entry per voxel) as calling octomap's updateNode(key, occupied)
/// `count` times per entry would, in any order. Reorders and shrinks nothing the caller keeps.
void applyUpdates(octomap::OcTree& tree, std::vector<VoxelUpdate>& updates);

}  // namespace hullmap::mapper::detail
