// insertScan: the tree octomap's insertPointCloud(points, origin, max_range) builds, built faster.
//
// octomap spends its time in two places: inserting every ray key into a shared unordered_set under an
// OpenMP critical section, and one updateNode per voxel, each a descent from the root (with a search
// first for its early abort). Here the rays are walked into per-thread bit bricks (ray_walk.cpp).
// All threads' bricks are sorted in Morton order; a brick marked by several threads is OR-ed
// (occupied wins over free, as in computeUpdate) when the update reaches it. The update is one
// depth-first pass that visits each node once, split by brick code above a brick's root and by the
// brick's bits below, and repeats octomap's per-key rules (early abort at clamped leaves, expansion of
// pruned leaves, child creation, pruning, inner-node maximum). Each voxel is updated once per scan,
// so the order of updates does not change the tree.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "hullmap/mapper/detail/octree_keys.hpp"
#include "hullmap/mapper/occupancy_map.hpp"

namespace hullmap::mapper {
namespace detail {

namespace {

// First item in [begin, end) (sorted by code) with code >= limit. Exponential search: the runs of
// one child are long near the root and short near the leaves, and a scan would read every item at
// every level.
template <typename Item>
Item* firstAtLeast(Item* begin, Item* end, std::uint64_t limit) {
  const std::size_t n = static_cast<std::size_t>(end - begin);
  std::size_t bound = 1;
  while (bound <= n && begin[bound - 1].code < limit) bound *= 2;
  return std::lower_bound(begin + bound / 2, begin + std::min(bound, n), limit,
                          [](const Item& item, std::uint64_t l) { return item.code < l; });
}

// LSD radix sort of items by their `code`, 13 bits a pass, `passes` passes (stable).
template <typename Item>
void radixSortByCode(std::vector<Item>& items, unsigned passes) {
  std::vector<Item> buffer(items.size());
  std::vector<std::size_t> count(1 << 13);
  for (unsigned pass = 0; pass < passes; ++pass) {
    const unsigned shift = 13 * pass;
    std::fill(count.begin(), count.end(), 0);
    for (const Item& item : items) ++count[(item.code >> shift) & 0x1FFF];
    std::size_t sum = 0;
    for (std::size_t& n : count) {
      const std::size_t here = n;
      n = sum;
      sum += here;
    }
    for (const Item& item : items) buffer[count[(item.code >> shift) & 0x1FFF]++] = item;
    items.swap(buffer);
  }
}

// octomap's node update, as updateNode applies it: a hit adds the hit log-odds, a miss the miss
// log-odds, and an update is skipped (search(key) stops there) when the node is already clamped on
// the side the update pushes towards.
struct UpdatePolicy {
  explicit UpdatePolicy(const octomap::OcTree& tree)
      : hit(tree.getProbHitLog()),
        miss(tree.getProbMissLog()),
        clamp_min(tree.getClampingThresMinLog()),
        clamp_max(tree.getClampingThresMaxLog()) {}
  float logOdds(bool occupied) const { return occupied ? hit : miss; }
  bool aborts(bool occupied, float v) const {
    const float update = logOdds(occupied);
    return (update >= 0 && v >= clamp_max) || (update <= 0 && v <= clamp_min);
  }
  float hit, miss, clamp_min, clamp_max;
};

class BatchUpdate {
 public:
  explicit BatchUpdate(octomap::OcTree& tree) : tree_(tree), policy_(tree) {}

  // Returns true when something below `node` changed (octomap then prunes or refreshes it).
  bool descend(octomap::OcTreeNode* node, bool just_created, unsigned depth, VoxelUpdate* begin, VoxelUpdate* end) {
    if (!just_created && !tree_.nodeHasChildren(node)) {
      // search(key) would stop here: octomap's early abort for updates that cannot change it.
      const float v = node->getLogOdds();
      end = std::remove_if(begin, end, [&](const VoxelUpdate& u) { return aborts(u.code, v); });
      if (begin == end) return false;
    }
    if (depth == kTreeDepth) {
      const float update = policy_.logOdds((begin->code & 1) != 0);
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
      VoxelUpdate* run = firstAtLeast(it + 1, end, ((it->code >> shift) + 1) << shift);
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
  bool aborts(std::uint64_t code, float v) const { return policy_.aborts((code & 1) != 0, v); }

  static constexpr unsigned kTreeDepth = 16;
  octomap::OcTree& tree_;
  UpdatePolicy policy_;
};

}  // namespace

void sortUpdates(std::vector<VoxelUpdate>& updates) {
  radixSortByCode(updates, 4);  // 49-bit codes
}

namespace {

void sortBricks(std::vector<ScanUpdate::Entry>& bricks) {
  radixSortByCode(bricks, 3);  // 39-bit codes
}

// The voxels of the entries [begin, end) of one brick: occupied, and free but not occupied.
void mergeBrick(const ScanUpdate& update, const ScanUpdate::Entry* begin, const ScanUpdate::Entry* end,
                std::uint64_t occupied[BrickSet::kWords], std::uint64_t free[BrickSet::kWords]) {
  for (std::size_t w = 0; w < BrickSet::kWords; ++w) occupied[w] = free[w] = 0;
  for (const ScanUpdate::Entry* e = begin; e != end; ++e) {
    const BrickSet& set = update.sets[e->set];
    for (std::size_t w = 0; w < BrickSet::kWords; ++w) {
      occupied[w] |= set.occupiedWords(e->brick)[w];
      free[w] |= set.freeWords(e->brick)[w];
    }
  }
  for (std::size_t w = 0; w < BrickSet::kWords; ++w) free[w] &= ~occupied[w];
}

const ScanUpdate::Entry* brickEnd(const ScanUpdate::Entry* it, const ScanUpdate::Entry* end) {
  const ScanUpdate::Entry* run = it + 1;
  while (run != end && run->code == it->code) ++run;
  return run;
}

std::uint64_t brickMorton(std::uint64_t c) {
  return mortonCode((c & 0x1FFF) | ((c >> 13) & 0x1FFF) << 16 | ((c >> 26) & 0x1FFF) << 32);
}

}  // namespace

ScanUpdate::ScanUpdate(std::vector<BrickSet> marked) : sets(std::move(marked)) {
  for (std::uint32_t t = 0; t < sets.size(); ++t) {
    for (std::uint32_t i = 0; i < sets[t].brickCount(); ++i) {
      if (!sets[t].empty(i)) bricks.push_back({brickMorton(sets[t].coordOf(i)), t, i});
    }
  }
  sortBricks(bricks);
}

std::size_t ScanUpdate::voxelCount() const {
  std::size_t n = 0;
  const Entry* end = bricks.data() + bricks.size();
  for (const Entry* it = bricks.data(); it != end;) {
    const Entry* run = brickEnd(it, end);
    std::uint64_t occupied[BrickSet::kWords], free[BrickSet::kWords];
    mergeBrick(*this, it, run, occupied, free);
    for (std::size_t w = 0; w < BrickSet::kWords; ++w) n += bitCount(occupied[w] | free[w]);
    it = run;
  }
  return n;
}

namespace {

// The depth-first pass of applyUpdates over a scan's bricks: above a brick's root (depth 13) the
// children are split by brick code; below it by the bits of its words (word w: child w at depth
// 14; in a word, bits 8c..8c+7: child c at depth 15; bit l of those: leaf l). Same rules as
// BatchUpdate::descend, on masks: at an existing leaf, octomap's early abort drops every
// occupied (or free) update below it when such an update cannot change the leaf.
class ScanApply {
 public:
  ScanApply(octomap::OcTree& tree, const ScanUpdate& update) : tree_(tree), update_(update), policy_(tree) {}

  /// Voxel `skip` (Morton code) is left out: the caller applied it already.
  void run(std::uint64_t skip) {
    skip_ = skip;
    const ScanUpdate::Entry* begin = update_.bricks.data();
    bricks(tree_.getRoot(), false, 0, begin, begin + update_.bricks.size(), false, false);
  }

 private:
  bool abortsOccupied(float v) const { return policy_.aborts(true, v); }
  bool abortsFree(float v) const { return policy_.aborts(false, v); }

  // Child `pos` of `node`, created (or `node` expanded) as updateNodeRecurs does.
  octomap::OcTreeNode* child(octomap::OcTreeNode* node, bool node_created, unsigned pos, bool& created) {
    created = false;
    if (!tree_.nodeChildExists(node, pos)) {
      if (!tree_.nodeHasChildren(node) && !node_created) {
        tree_.expandNode(node);
      } else {
        tree_.createNodeChild(node, pos);
        created = true;
      }
    }
    return tree_.getNodeChild(node, pos);
  }

  bool finish(octomap::OcTreeNode* node, bool changed) {
    if (changed && !tree_.pruneNode(node)) node->updateOccupancyChildren();
    return changed;
  }

  void masks(const ScanUpdate::Entry* begin, const ScanUpdate::Entry* end, bool drop_occupied, bool drop_free,
             std::uint64_t occupied[BrickSet::kWords], std::uint64_t free[BrickSet::kWords]) const {
    mergeBrick(update_, begin, end, occupied, free);
    if ((begin->code << 9) == (skip_ & ~std::uint64_t{511})) {
      occupied[(skip_ >> 6) & 7] &= ~(std::uint64_t{1} << (skip_ & 63));
      free[(skip_ >> 6) & 7] &= ~(std::uint64_t{1} << (skip_ & 63));
    }
    for (std::size_t w = 0; w < BrickSet::kWords; ++w) {
      if (drop_occupied) occupied[w] = 0;
      if (drop_free) free[w] = 0;
    }
  }

  bool anyLeft(const ScanUpdate::Entry* begin, const ScanUpdate::Entry* end, bool drop_occupied, bool drop_free) const {
    for (const ScanUpdate::Entry* it = begin; it != end;) {
      const ScanUpdate::Entry* run = brickEnd(it, end);
      std::uint64_t occupied[BrickSet::kWords], free[BrickSet::kWords];
      masks(it, run, drop_occupied, drop_free, occupied, free);
      for (std::size_t w = 0; w < BrickSet::kWords; ++w) {
        if ((occupied[w] | free[w]) != 0) return true;
      }
      it = run;
    }
    return false;
  }

  // Depth 0..12: children split by brick code.
  bool bricks(octomap::OcTreeNode* node, bool just_created, unsigned depth, const ScanUpdate::Entry* begin,
              const ScanUpdate::Entry* end, bool drop_occupied, bool drop_free) {
    if (!just_created && !tree_.nodeHasChildren(node)) {
      const float v = node->getLogOdds();
      drop_occupied |= abortsOccupied(v);
      drop_free |= abortsFree(v);
      if ((drop_occupied || drop_free) && !anyLeft(begin, end, drop_occupied, drop_free)) return false;
    }
    const unsigned shift = 3 * (12 - depth);
    bool changed = false;
    for (const ScanUpdate::Entry* it = begin; it != end;) {
      const unsigned pos = static_cast<unsigned>((it->code >> shift) & 7);
      const ScanUpdate::Entry* run = firstAtLeast(it + 1, end, ((it->code >> shift) + 1) << shift);
      bool created;
      octomap::OcTreeNode* next = child(node, just_created, pos, created);
      if (depth + 1 < kBrickDepth) {
        changed |= bricks(next, created, depth + 1, it, run, drop_occupied, drop_free);
      } else {
        std::uint64_t occupied[BrickSet::kWords], free[BrickSet::kWords];
        masks(it, run, drop_occupied, drop_free, occupied, free);
        changed |= brick(next, created, occupied, free);
      }
      it = run;
    }
    return finish(node, changed);
  }

  // Depth 13: a brick's root; child w has word w.
  bool brick(octomap::OcTreeNode* node, bool just_created, std::uint64_t occupied[BrickSet::kWords],
             std::uint64_t free[BrickSet::kWords]) {
    std::uint64_t any = 0;
    if (!just_created && !tree_.nodeHasChildren(node)) {
      const float v = node->getLogOdds();
      const bool drop_occupied = abortsOccupied(v), drop_free = abortsFree(v);
      for (std::size_t w = 0; w < BrickSet::kWords; ++w) {
        if (drop_occupied) occupied[w] = 0;
        if (drop_free) free[w] = 0;
      }
    }
    std::uint64_t all_occupied = ~std::uint64_t{0}, all_free = ~std::uint64_t{0};
    for (std::size_t w = 0; w < BrickSet::kWords; ++w) {
      any |= occupied[w] | free[w];
      all_occupied &= occupied[w];
      all_free &= free[w];
    }
    if (any == 0) return false;
    if (just_created && (all_occupied == ~std::uint64_t{0} || all_free == ~std::uint64_t{0})) {
      return collapsed(node, all_occupied == ~std::uint64_t{0});
    }
    bool changed = false;
    for (unsigned w = 0; w < BrickSet::kWords; ++w) {
      if ((occupied[w] | free[w]) == 0) continue;
      bool created;
      octomap::OcTreeNode* next = child(node, just_created, w, created);
      changed |= word(next, created, occupied[w], free[w]);
    }
    return finish(node, changed);
  }

  // Depth 14 (64 voxels, child c: bits 8c..8c+7) and 15 (8 voxels, child c: bit c).
  bool word(octomap::OcTreeNode* node, bool just_created, std::uint64_t occupied, std::uint64_t free,
            unsigned depth = 14) {
    if (!just_created && !tree_.nodeHasChildren(node)) {
      const float v = node->getLogOdds();
      if (abortsOccupied(v)) occupied = 0;
      if (abortsFree(v)) free = 0;
    }
    if ((occupied | free) == 0) return false;
    const std::uint64_t all = depth == 14 ? ~std::uint64_t{0} : 0xFF;
    if (just_created && (occupied == all || free == all)) return collapsed(node, occupied == all);
    const unsigned width = depth == 14 ? 8 : 1;
    const std::uint64_t mask = depth == 14 ? 0xFF : 1;
    bool changed = false;
    for (unsigned c = 0; c < 8; ++c) {
      const std::uint64_t o = (occupied >> (width * c)) & mask, f = (free >> (width * c)) & mask;
      if ((o | f) == 0) continue;
      bool created;
      octomap::OcTreeNode* next = child(node, just_created, c, created);
      changed |= depth == 14 ? word(next, created, o, f, 15) : leaf(next, created, o != 0);
    }
    return finish(node, changed);
  }

  // A new node whose voxels all get the same update: octomap would create its children, update
  // each once from 0 (the same value for all) and prune them into it, leaving the node a leaf with
  // that value, which is the node updated once from its own 0. Saves the children's allocations.
  bool collapsed(octomap::OcTreeNode* node, bool occupied) {
    tree_.updateNodeLogOdds(node, policy_.logOdds(occupied));
    return true;
  }

  bool leaf(octomap::OcTreeNode* node, bool just_created, bool occupied) {
    if (!just_created && (occupied ? abortsOccupied(node->getLogOdds()) : abortsFree(node->getLogOdds()))) {
      return false;
    }
    tree_.updateNodeLogOdds(node, policy_.logOdds(occupied));
    return true;
  }

  static constexpr unsigned kBrickDepth = 13;
  octomap::OcTree& tree_;
  const ScanUpdate& update_;
  UpdatePolicy policy_;
  std::uint64_t skip_ = ~std::uint64_t{0};
};

}  // namespace

void applyScanUpdate(octomap::OcTree& tree, const ScanUpdate& update) {
  if (update.bricks.empty()) return;
  std::uint64_t skip = ~std::uint64_t{0};
  if (tree.getRoot() == nullptr) {
    // Only octomap can create the root: the first voxel's update goes through updateNode.
    const ScanUpdate::Entry* begin = update.bricks.data();
    const ScanUpdate::Entry* run = brickEnd(begin, begin + update.bricks.size());
    std::uint64_t occupied[BrickSet::kWords], free[BrickSet::kWords];
    mergeBrick(update, begin, run, occupied, free);
    for (unsigned w = 0; w < BrickSet::kWords && skip == ~std::uint64_t{0}; ++w) {
      const std::uint64_t any = occupied[w] | free[w];
      if (any == 0) continue;
      const unsigned bit = static_cast<unsigned>(__builtin_ctzll(any));
      skip = begin->code << 9 | w << 6 | bit;
      tree.updateNode(mortonKey(skip), ((occupied[w] >> bit) & 1) != 0);
    }
  }
  ScanApply(tree, update).run(skip);
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

void insertScan(octomap::OcTree& tree, const io::Points& points, const io::Point& origin, double max_range) {
  if (tree.bbxSet() || tree.isChangeDetectionEnabled()) {
    // Rare configurations: let octomap do it.
    octomap::Pointcloud cloud;
    cloud.reserve(points.size());
    for (const io::Point& p : points)
      cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    tree.insertPointCloud(cloud,
                          octomap::point3d(static_cast<float>(origin.x()), static_cast<float>(origin.y()),
                                           static_cast<float>(origin.z())),
                          max_range);
    return;
  }
  detail::applyScanUpdate(tree, detail::computeScanUpdate(tree, points, origin, max_range));
}

}  // namespace hullmap::mapper
