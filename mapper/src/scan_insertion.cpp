// insertScan: the tree octomap's insertPointCloud(points, origin, max_range) builds, built faster.
//
// octomap spends its time in two places: inserting every ray key into a shared unordered_set under an
// OpenMP critical section, and one updateNode per voxel, each a descent from the root (with a search
// first for its early abort). Here each thread casts its share of the rays with the same DDA
// arithmetic into its own set of 8x8x8 bit bricks; the bricks are merged in Morton order (occupied
// wins over free, as in computeUpdate), which yields the voxels already sorted in octree order; they
// are applied in one depth-first pass that visits each node once and repeats octomap's per-key rules
// (early abort at clamped leaves, expansion of pruned leaves, child creation, pruning, inner-node
// maximum). Each voxel is updated once per scan, so the order of updates does not change the tree.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "hullmap/mapper/occupancy_map.hpp"
#include "octree_keys.hpp"

namespace hullmap::mapper {
namespace detail {

namespace {

std::uint64_t spreadBits(std::uint64_t v) {
  v &= 0xFFFF;
  v = (v | (v << 16)) & 0x0000FF0000FFull;
  v = (v | (v << 8)) & 0x00F00F00F00Full;
  v = (v | (v << 4)) & 0x0C30C30C30C3ull;
  v = (v | (v << 2)) & 0x249249249249ull;
  return v;
}

std::uint64_t compactBits(std::uint64_t v) {
  v &= 0x249249249249ull;
  v = (v | (v >> 2)) & 0x0C30C30C30C3ull;
  v = (v | (v >> 4)) & 0x00F00F00F00Full;
  v = (v | (v >> 8)) & 0x0000FF0000FFull;
  v = (v | (v >> 16)) & 0xFFFF;
  return v;
}

}  // namespace

std::uint64_t mortonCode(std::uint64_t packed) {
  return spreadBits(packed) | (spreadBits(packed >> 16) << 1) | (spreadBits(packed >> 32) << 2);
}

octomap::OcTreeKey mortonKey(std::uint64_t morton) {
  return octomap::OcTreeKey(static_cast<octomap::key_type>(compactBits(morton)),
                            static_cast<octomap::key_type>(compactBits(morton >> 1)),
                            static_cast<octomap::key_type>(compactBits(morton >> 2)));
}

std::uint32_t BrickSet::find(std::uint64_t coord) {
  if (2 * (bricks_.size() + 1) > slots_.size()) {
    const std::size_t capacity = std::max<std::size_t>(4096, 2 * slots_.size());
    slots_.assign(capacity, 0);
    slot_index_.assign(capacity, 0);
    shift_ = 64 - static_cast<unsigned>(std::log2(static_cast<double>(capacity)) + 0.5);
    for (std::uint32_t i = 0; i < coords_.size(); ++i) {
      std::size_t s = static_cast<std::size_t>((coords_[i] * 0x9E3779B97F4A7C15ull) >> shift_);
      while (slots_[s] != 0) s = (s + 1) & (capacity - 1);
      slots_[s] = coords_[i] + 1;
      slot_index_[s] = i;
    }
  }
  std::size_t s = static_cast<std::size_t>((coord * 0x9E3779B97F4A7C15ull) >> shift_);
  while (slots_[s] != 0) {
    if (slots_[s] == coord + 1) return slot_index_[s];
    s = (s + 1) & (slots_.size() - 1);
  }
  slots_[s] = coord + 1;
  slot_index_[s] = static_cast<std::uint32_t>(bricks_.size());
  bricks_.emplace_back();
  coords_.push_back(coord);
  return slot_index_[s];
}

KeyCaster::KeyCaster(const octomap::OcTree& tree)
    : resolution_(tree.getResolution()), resolution_factor_(1.0 / tree.getResolution()),
      max_val_(32768) {}

bool KeyCaster::coordToKeyChecked(double coordinate, int& key) const {
  const double scaled = std::floor(resolution_factor_ * coordinate);
  // octomap casts first; outside int's range (and for NaN) that is undefined, and never a valid key.
  if (!(scaled > -2147483648.0 && scaled < 2147483647.0)) return false;
  const int k = static_cast<int>(scaled) + max_val_;
  if (k < 0 || k >= 2 * max_val_) return false;
  key = k;
  return true;
}

bool KeyCaster::coordToKeyChecked(const octomap::point3d& p, int key[3]) const {
  return coordToKeyChecked(p(0), key[0]) && coordToKeyChecked(p(1), key[1]) && coordToKeyChecked(p(2), key[2]);
}

// Same arithmetic, statement for statement, as OcTreeBaseImpl::computeRayKeys (octomap 1.9),
// without KeyRay's fixed 100000-key buffer.
bool KeyCaster::castRay(const octomap::point3d& origin, const octomap::point3d& end, BrickSet& out) const {
  int key_origin[3], key_end[3];
  if (!coordToKeyChecked(origin, key_origin) || !coordToKeyChecked(end, key_end)) return false;
  if (key_origin[0] == key_end[0] && key_origin[1] == key_end[1] && key_origin[2] == key_end[2]) return true;

  out.mark(key_origin, false);

  octomap::point3d direction = (end - origin);
  const float length = static_cast<float>(direction.norm());
  direction /= length;

  int step[3];
  double t_max[3];
  double t_delta[3];
  int current[3] = {key_origin[0], key_origin[1], key_origin[2]};
  for (int i = 0; i < 3; ++i) {
    if (direction(i) > 0.0) step[i] = 1;
    else if (direction(i) < 0.0) step[i] = -1;
    else step[i] = 0;

    if (step[i] != 0) {
      double voxel_border = (static_cast<double>(current[i] - max_val_) + 0.5) * resolution_;
      voxel_border += static_cast<float>(step[i] * resolution_ * 0.5);
      t_max[i] = (voxel_border - origin(i)) / direction(i);
      t_delta[i] = resolution_ / std::fabs(direction(i));
    } else {
      t_max[i] = std::numeric_limits<double>::max();
      t_delta[i] = std::numeric_limits<double>::max();
    }
  }

  for (;;) {
    int dim;
    if (t_max[0] < t_max[1]) dim = t_max[0] < t_max[2] ? 0 : 2;
    else dim = t_max[1] < t_max[2] ? 1 : 2;

    // octomap's keys are 16-bit: stepping past the edge wraps.
    current[dim] = (current[dim] + step[dim]) & 0xFFFF;
    t_max[dim] += t_delta[dim];

    if (current[0] == key_end[0] && current[1] == key_end[1] && current[2] == key_end[2]) break;
    const double dist_from_origin = std::min(std::min(t_max[0], t_max[1]), t_max[2]);
    if (dist_from_origin > length) break;
    out.mark(current, false);
  }
  return true;
}

namespace {

class BatchUpdate {
 public:
  explicit BatchUpdate(octomap::OcTree& tree)
      : tree_(tree), hit_(tree.getProbHitLog()), miss_(tree.getProbMissLog()),
        clamp_min_(tree.getClampingThresMinLog()), clamp_max_(tree.getClampingThresMaxLog()) {}

  // Returns true when something below `node` changed (octomap then prunes or refreshes it).
  bool descend(octomap::OcTreeNode* node, bool just_created, unsigned depth, VoxelUpdate* begin,
               VoxelUpdate* end) {
    if (!just_created && !tree_.nodeHasChildren(node)) {
      // search(key) would stop here: octomap's early abort for updates that cannot change it.
      const float v = node->getLogOdds();
      end = std::remove_if(begin, end, [&](const VoxelUpdate& u) { return aborts(u.code, v); });
      if (begin == end) return false;
    }
    if (depth == kTreeDepth) {
      const float update = (begin->code & 1) ? hit_ : miss_;
      tree_.updateNodeLogOdds(node, update);
      for (std::uint32_t i = 1; i < begin->count && !aborts(begin->code, node->getLogOdds()); ++i) {
        tree_.updateNodeLogOdds(node, update);
      }
      return true;
    }
    const unsigned shift = 1 + 3 * (kTreeDepth - 1 - depth);
    bool changed = false;
    for (VoxelUpdate* it = begin; it != end;) {
      const unsigned pos = static_cast<unsigned>((it->code >> shift) & 7);
      VoxelUpdate* run = it + 1;
      while (run != end && static_cast<unsigned>((run->code >> shift) & 7) == pos) ++run;
      bool created = false;
      if (!tree_.nodeChildExists(node, pos)) {
        if (!tree_.nodeHasChildren(node) && !just_created) {
          tree_.expandNode(node);
        } else {
          tree_.createNodeChild(node, pos);
          created = true;
        }
      }
      changed |= descend(tree_.getNodeChild(node, pos), created, depth + 1, it, run);
      it = run;
    }
    if (changed && !tree_.pruneNode(node)) node->updateOccupancyChildren();
    return changed;
  }

 private:
  bool aborts(std::uint64_t code, float v) const {
    const float update = (code & 1) ? hit_ : miss_;
    return (update >= 0 && v >= clamp_max_) || (update <= 0 && v <= clamp_min_);
  }

  static constexpr unsigned kTreeDepth = 16;
  octomap::OcTree& tree_;
  float hit_, miss_, clamp_min_, clamp_max_;
};

}  // namespace

void sortUpdates(std::vector<VoxelUpdate>& updates) {
  // 49-bit codes: four passes of 13 bits.
  std::vector<VoxelUpdate> buffer(updates.size());
  std::vector<std::size_t> count(1 << 13);
  for (unsigned pass = 0; pass < 4; ++pass) {
    const unsigned shift = 13 * pass;
    std::fill(count.begin(), count.end(), 0);
    for (const VoxelUpdate& u : updates) ++count[(u.code >> shift) & 0x1FFF];
    std::size_t sum = 0;
    for (std::size_t& n : count) {
      const std::size_t here = n;
      n = sum;
      sum += here;
    }
    for (const VoxelUpdate& u : updates) buffer[count[(u.code >> shift) & 0x1FFF]++] = u;
    updates.swap(buffer);
  }
}

std::vector<VoxelUpdate> computeScanUpdate(const octomap::OcTree& tree, const Points& points,
                                           const Point& origin_d, double max_range) {
  const KeyCaster caster(tree);
  const octomap::point3d origin(static_cast<float>(origin_d.x()), static_cast<float>(origin_d.y()),
                                static_cast<float>(origin_d.z()));
  tbb::enumerable_thread_specific<BrickSet> local;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& range) {
    BrickSet& set = local.local();
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const octomap::point3d p(static_cast<float>(points[i].x()), static_cast<float>(points[i].y()),
                               static_cast<float>(points[i].z()));
      if (max_range < 0.0 || (p - origin).norm() <= max_range) {
        caster.castRay(origin, p, set);
        int key[3];
        if (caster.coordToKeyChecked(p, key)) set.mark(key, true);
      } else {
        const octomap::point3d direction = (p - origin).normalized();
        const octomap::point3d new_end = origin + direction * static_cast<float>(max_range);
        caster.castRay(origin, new_end, set);
      }
    }
  });

  // All threads' bricks in brick Morton order; bricks of one coordinate are OR-ed.
  std::vector<const BrickSet*> sets;
  for (const BrickSet& set : local) sets.push_back(&set);
  std::vector<VoxelUpdate> order;  // code: brick Morton; count: set << 27 | brick index
  for (std::uint32_t t = 0; t < sets.size(); ++t) {
    const auto& coords = sets[t]->coords();
    for (std::uint32_t i = 0; i < coords.size(); ++i) {
      const std::uint64_t c = coords[i];
      const std::uint64_t packed = (c & 0x1FFF) | ((c >> 13) & 0x1FFF) << 16 | ((c >> 26) & 0x1FFF) << 32;
      order.push_back({mortonCode(packed), t << 27 | i});
    }
  }
  sortUpdates(order);
  std::vector<VoxelUpdate> updates;
  for (std::size_t i = 0; i < order.size();) {
    BrickSet::Brick merged;
    std::size_t j = i;
    for (; j < order.size() && order[j].code == order[i].code; ++j) {
      const BrickSet::Brick& b = sets[order[j].count >> 27]->bricks()[order[j].count & 0x7FFFFFF];
      for (int w = 0; w < 8; ++w) {
        merged.free[w] |= b.free[w];
        merged.occupied[w] |= b.occupied[w];
      }
    }
    const std::uint64_t base = order[i].code << 9;
    for (unsigned w = 0; w < 8; ++w) {
      const std::uint64_t occupied = merged.occupied[w];
      std::uint64_t any = merged.free[w] | occupied;  // occupied wins over free
      while (any != 0) {
        const unsigned bit = static_cast<unsigned>(__builtin_ctzll(any));
        any &= any - 1;
        updates.push_back({(base | (w << 6) | bit) << 1 | ((occupied >> bit) & 1), 1});
      }
    }
    i = j;
  }
  return updates;
}

void applyUpdates(octomap::OcTree& tree, std::vector<VoxelUpdate>& updates) {
  if (updates.empty()) return;
  std::size_t first = 0;
  if (tree.getRoot() == nullptr) {
    // Only octomap can create the root: the first voxel's first update goes through updateNode.
    const VoxelUpdate& u = updates[0];
    tree.updateNode(mortonKey(u.code >> 1), (u.code & 1) != 0);
    if (u.count > 1) {
      updates[0].count -= 1;
    } else {
      first = 1;
    }
  }
  BatchUpdate batch(tree);
  batch.descend(tree.getRoot(), false, 0, updates.data() + first, updates.data() + updates.size());
}

}  // namespace detail

void insertScan(octomap::OcTree& tree, const Points& points, const Point& origin, double max_range) {
  if (tree.bbxSet() || tree.isChangeDetectionEnabled()) {
    // Rare configurations: let octomap do it.
    octomap::Pointcloud cloud;
    cloud.reserve(points.size());
    for (const Point& p : points) cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    tree.insertPointCloud(cloud, octomap::point3d(static_cast<float>(origin.x()), static_cast<float>(origin.y()),
                                                  static_cast<float>(origin.z())),
                          max_range);
    return;
  }
  std::vector<detail::VoxelUpdate> updates = detail::computeScanUpdate(tree, points, origin, max_range);
  detail::applyUpdates(tree, updates);
}

}  // namespace hullmap::mapper
