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

BrickSet::BrickSet(const int lo[3], const int dims[3]) {
  for (int i = 0; i < 3; ++i) {
    lo_[i] = lo[i];
    dims_[i] = dims[i];
  }
  dense_count_ = static_cast<std::size_t>(dims[0]) * dims[1] * dims[2];
  bricks_.resize(dense_count_);
}

std::uint64_t BrickSet::coordOf(std::size_t i) const {
  if (i >= dense_count_) return coords_[i - dense_count_];
  const std::uint64_t x = lo_[0] + i % dims_[0];
  const std::uint64_t y = lo_[1] + (i / dims_[0]) % dims_[1];
  const std::uint64_t z = lo_[2] + i / (static_cast<std::size_t>(dims_[0]) * dims_[1]);
  return x | y << 13 | z << 26;
}

std::uint32_t BrickSet::find(std::uint64_t coord) {
  const unsigned x = static_cast<unsigned>(coord & 0x1FFF) - lo_[0];
  const unsigned y = static_cast<unsigned>((coord >> 13) & 0x1FFF) - lo_[1];
  const unsigned z = static_cast<unsigned>(coord >> 26) - lo_[2];
  if (x < static_cast<unsigned>(dims_[0]) && y < static_cast<unsigned>(dims_[1]) && z < static_cast<unsigned>(dims_[2])) {
    return static_cast<std::uint32_t>((static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0] + x);
  }
  if (2 * (coords_.size() + 1) > slots_.size()) {
    const std::size_t capacity = std::max<std::size_t>(4096, 2 * slots_.size());
    slots_.assign(capacity, 0);
    slot_index_.assign(capacity, 0);
    shift_ = 64 - static_cast<unsigned>(std::log2(static_cast<double>(capacity)) + 0.5);
    for (std::uint32_t i = 0; i < coords_.size(); ++i) {
      std::size_t s = static_cast<std::size_t>((coords_[i] * 0x9E3779B97F4A7C15ull) >> shift_);
      while (slots_[s] != 0) s = (s + 1) & (capacity - 1);
      slots_[s] = coords_[i] + 1;
      slot_index_[s] = static_cast<std::uint32_t>(dense_count_ + i);
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

namespace {

struct OrderedBrick {
  std::uint64_t code;  // brick Morton
  const BrickSet::Brick* brick;
};

void sortBricks(std::vector<OrderedBrick>& bricks) {
  // 39-bit codes: three passes of 13 bits.
  std::vector<OrderedBrick> buffer(bricks.size());
  std::vector<std::size_t> count(1 << 13);
  for (unsigned pass = 0; pass < 3; ++pass) {
    const unsigned shift = 13 * pass;
    std::fill(count.begin(), count.end(), 0);
    for (const auto& b : bricks) ++count[(b.code >> shift) & 0x1FFF];
    std::size_t sum = 0;
    for (std::size_t& n : count) {
      const std::size_t here = n;
      n = sum;
      sum += here;
    }
    for (const auto& b : bricks) buffer[count[(b.code >> shift) & 0x1FFF]++] = b;
    bricks.swap(buffer);
  }
}

std::uint64_t brickMorton(std::uint64_t c) {
  return mortonCode((c & 0x1FFF) | ((c >> 13) & 0x1FFF) << 16 | ((c >> 26) & 0x1FFF) << 32);
}

// Per-thread dense bricks cost memory and zeroing: only for boxes that are not much larger
// than the work.
constexpr std::size_t kMaxDenseBricks = std::size_t{1} << 18;  // 32 MiB per thread

}  // namespace

std::vector<VoxelUpdate> computeScanUpdate(const octomap::OcTree& tree, const Points& points,
                                           const Point& origin_d, double max_range) {
  const KeyCaster caster(tree);
  const octomap::point3d origin(static_cast<float>(origin_d.x()), static_cast<float>(origin_d.y()),
                                static_cast<float>(origin_d.z()));
  auto toPoint3d = [](const Point& q) {
    return octomap::point3d(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
  };
  // Where each ray ends, as insertPointCloud decides (the measured point, or cut at max_range).
  auto rayEnd = [&](const octomap::point3d& p, bool& endpoint) {
    endpoint = max_range < 0.0 || (p - origin).norm() <= max_range;
    if (endpoint) return p;
    const octomap::point3d direction = (p - origin).normalized();
    return origin + direction * static_cast<float>(max_range);
  };

  // Box of the ray ends' bricks (rays stay between their ends' keys, give or take a voxel).
  struct Box {
    int lo[3] = {1 << 30, 1 << 30, 1 << 30};
    int hi[3] = {-1, -1, -1};
  };
  tbb::enumerable_thread_specific<Box> boxes;
  int origin_key[3];
  const bool origin_ok = caster.coordToKeyChecked(origin, origin_key);
  if (origin_ok) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4096),
                      [&](const tbb::blocked_range<std::size_t>& range) {
      Box& box = boxes.local();
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        bool endpoint;
        int key[3];
        if (!caster.coordToKeyChecked(rayEnd(toPoint3d(points[i]), endpoint), key)) continue;
        for (int a = 0; a < 3; ++a) {
          box.lo[a] = std::min(box.lo[a], key[a] >> 3);
          box.hi[a] = std::max(box.hi[a], key[a] >> 3);
        }
      }
    });
  }
  int lo[3], dims[3] = {0, 0, 0};
  std::size_t dense = 0;
  if (origin_ok) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = origin_key[a] >> 3;
      int hi = lo[a];
      for (const Box& box : boxes) {
        lo[a] = std::min(lo[a], box.lo[a]);
        hi = std::max(hi, box.hi[a]);
      }
      lo[a] = std::max(0, lo[a] - 1);
      dims[a] = std::min(8191, hi + 1) - lo[a] + 1;
    }
    dense = static_cast<std::size_t>(dims[0]) * dims[1] * dims[2];
    if (dense > kMaxDenseBricks || dense > 64 * points.size() + 4096) dims[0] = dims[1] = dims[2] = 0;
  }

  tbb::enumerable_thread_specific<BrickSet> local([&] { return BrickSet(lo, dims); });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& range) {
    BrickSet& set = local.local();
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const octomap::point3d p = toPoint3d(points[i]);
      bool endpoint;
      const octomap::point3d end = rayEnd(p, endpoint);
      caster.castRay(origin, end, set);
      int key[3];
      if (endpoint && caster.coordToKeyChecked(p, key)) set.mark(key, true);
    }
  });

  std::vector<BrickSet*> sets;
  for (BrickSet& set : local) sets.push_back(&set);
  if (sets.empty()) return {};
  // Dense boxes: OR into the first set's.
  BrickSet& first = *sets[0];
  const std::size_t dense_count = first.denseCount();
  if (sets.size() > 1 && dense_count > 0) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, dense_count, 4096),
                      [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t t = 1; t < sets.size(); ++t) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          BrickSet::Brick& into = first.bricks()[i];
          const BrickSet::Brick& from = sets[t]->bricks()[i];
          for (int w = 0; w < 8; ++w) {
            into.free[w] |= from.free[w];
            into.occupied[w] |= from.occupied[w];
          }
        }
      }
    });
  }
  std::vector<OrderedBrick> order;
  for (std::size_t i = 0; i < dense_count; ++i) {
    if (!first.bricks()[i].empty()) order.push_back({brickMorton(first.coordOf(i)), &first.bricks()[i]});
  }
  for (const BrickSet* set : sets) {
    for (std::size_t i = set->denseCount(); i < set->bricks().size(); ++i) {
      order.push_back({brickMorton(set->coordOf(i)), &set->bricks()[i]});
    }
  }
  sortBricks(order);

  // Voxels in Morton order; occupied wins over free.
  std::vector<VoxelUpdate> updates;
  for (std::size_t i = 0; i < order.size();) {
    BrickSet::Brick merged;
    std::size_t j = i;
    for (; j < order.size() && order[j].code == order[i].code; ++j) {
      for (int w = 0; w < 8; ++w) {
        merged.free[w] |= order[j].brick->free[w];
        merged.occupied[w] |= order[j].brick->occupied[w];
      }
    }
    const std::uint64_t base = order[i].code << 9;
    for (unsigned w = 0; w < 8; ++w) {
      const std::uint64_t occupied = merged.occupied[w];
      std::uint64_t any = merged.free[w] | occupied;
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
