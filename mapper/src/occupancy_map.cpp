#include "hullmap/mapper/occupancy_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>

#include <octomap/AbstractOcTree.h>
#include <tbb/parallel_for.h>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/mapper/detail/octree_keys.hpp"
#include "keyframe_index.hpp"
#include "octree_file.hpp"

namespace hullmap::mapper {
namespace {

constexpr unsigned kTreeDepth = 16;

// Debian's liboctomap is built with its debug output on: OccupancyOcTreeBase::writeBinaryData (which
// writeBinary and writeBinaryConst call) prints "Writing N nodes to output stream... done." on
// stderr. hullmap writes the .bt header itself and hands octomap only the node stream
// (writeBinaryNode, which prints nothing): the same bytes as writeBinaryConst, and the process's
// stderr is left alone. Reading calls readBinaryData / readData, which print nothing on a good
// stream; .ot writing (AbstractOcTree::write -> writeData) prints nothing either.
bool writeBinaryQuietly(const octomap::OcTree& tree, std::ostream& out) {
  out << "# Octomap OcTree binary file\n# (feel free to add / change comments, but leave the first line as it "
         "is!)\n#\n";
  out << "id " << tree.getTreeType() << std::endl;
  out << "size " << tree.size() << std::endl;
  out << "res " << tree.getResolution() << std::endl;
  out << "data" << std::endl;
  if (tree.getRoot() != nullptr) tree.writeBinaryNode(out, tree.getRoot());
  return out.good();
}

// occupiedVoxels() lists at most this many finest voxels (52 bytes each at the peak: ~1.7 GB).
constexpr std::uint64_t kMaxOccupiedVoxels = std::uint64_t(1) << 25;

void checkParams(const OctreeParams& p) {
  auto require = [](bool ok, const std::string& parameter, const std::string& what) {
    if (!ok) throw Error::inParameter(parameter, what);
  };
  require(std::isfinite(p.resolution) && p.resolution > 0.0, "resolution", "must be a positive number of map units");
  const SensorModel& s = p.sensor;
  const std::string probability = "must be a probability in (0, 1)";
  require(s.hit > 0.0 && s.hit < 1.0, "hit", probability);
  require(s.miss > 0.0 && s.miss < 1.0, "miss", probability);
  require(s.clamp_min > 0.0 && s.clamp_min < 1.0, "clamp_min", probability);
  require(s.clamp_max > 0.0 && s.clamp_max < 1.0, "clamp_max", probability);
  require(s.clamp_min < s.clamp_max, "clamp_min/clamp_max", "the lower clamp must be below the upper one");
  require(s.occupancy_threshold > 0.0 && s.occupancy_threshold < 1.0, "occupancy_threshold", probability);
  require(!std::isnan(p.max_range), "max_range", "must be a number");
}

octomap::point3d toPoint3d(const io::Point& p) {
  return octomap::point3d(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
}

bool lessKey(const octomap::OcTreeKey& a, const octomap::OcTreeKey& b) {
  if (a[0] != b[0]) return a[0] < b[0];
  if (a[1] != b[1]) return a[1] < b[1];
  return a[2] < b[2];
}

// Appends the codes (Morton << 1 | 1, count 1) of the points octomap can address (float
// coordinates, as its point3d API) to `codes`, in input order; ok[i] says whether points[i] was one.
// Returns how many were not.
std::size_t appendCodes(const detail::KeyCaster& caster, const io::Point* points, std::size_t n,
                        std::vector<detail::VoxelUpdate>& codes, std::vector<char>& ok) {
  const std::size_t first = codes.size();
  codes.resize(first + n);
  ok.resize(n);
  detail::VoxelUpdate* out = codes.data() + first;
  tbb::parallel_for(std::size_t{0}, n, std::size_t{4096}, [&](std::size_t begin) {
    const std::size_t end = std::min(n, begin + 4096);
    for (std::size_t i = begin; i < end; ++i) {
      int key[3] = {0, 0, 0};
      ok[i] = caster.coordToKeyChecked(toPoint3d(points[i]), key);
      out[i].code = ok[i] ? (detail::mortonCode(detail::pack(key)) << 1 | 1) : ~std::uint64_t{0};
    }
  });
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (ok[i]) out[kept++] = out[i];
  }
  codes.resize(first + kept);
  return n - kept;
}

// Sorted codes -> one entry per voxel, counts summed.
void collapseRuns(std::vector<detail::VoxelUpdate>& codes) {
  std::size_t runs = 0;
  for (std::size_t i = 0; i < codes.size();) {
    std::uint32_t count = 0;
    std::size_t j = i;
    for (; j < codes.size() && codes[j].code == codes[i].code; ++j) count += codes[j].count;
    codes[runs++] = {codes[i].code, count};
    i = j;
  }
  codes.resize(runs);
}

// Keys of the addressable points as sorted (Morton << 1 | 1, count) runs; the others are counted
// as out_of_octree.
std::vector<detail::VoxelUpdate> countPoints(const octomap::OcTree& tree, const io::Points& points,
                                             std::vector<char>& addressable_flags, std::size_t& dropped) {
  std::vector<detail::VoxelUpdate> codes;
  dropped = appendCodes(detail::KeyCaster(tree), points.data(), points.size(), codes, addressable_flags);
  detail::sortUpdates(codes);
  collapseRuns(codes);
  return codes;
}

void recordCounts(OccupancyMap& map, const std::vector<detail::VoxelUpdate>& runs) {
  auto& counts = map.pointCounts();
  counts.reserve(counts.size() + runs.size());
  for (const auto& r : runs) counts[detail::mortonKey(r.code >> 1)] += r.count;
}

void addDropped(io::InputStats& stats, std::size_t dropped) {
  if (dropped > 0) stats.dropped["out_of_octree"] += dropped;
}

std::string extensionOf(const std::string& path) {
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || path.find_first_of('/', dot) != std::string::npos) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

OccupancyMap::OccupancyMap(const OctreeParams& params) {
  checkParams(params);
  tree_ = std::make_unique<octomap::OcTree>(params.resolution);
  tree_->setProbHit(params.sensor.hit);
  tree_->setProbMiss(params.sensor.miss);
  tree_->setClampingThresMin(params.sensor.clamp_min);
  tree_->setClampingThresMax(params.sensor.clamp_max);
  tree_->setOccupancyThres(params.sensor.occupancy_threshold);
}

std::vector<OccupiedVoxel> OccupancyMap::occupiedVoxels() const {
  struct Entry {
    octomap::OcTreeKey key;
    float log_odds;
  };
  // A pruned leaf at depth d stands for 8^(16 - d) finest voxels: one near the root of a 140-byte
  // .bt is 2^45 of them. Count before expanding, and refuse what cannot be listed.
  std::uint64_t total = 0;
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
    if (tree_->isNodeOccupied(*it)) total += std::uint64_t(1) << (3 * (kTreeDepth - it.getDepth()));
    if (total > kMaxOccupiedVoxels) {
      std::ostringstream what;
      what << "octree: its occupied leaves stand for more than " << kMaxOccupiedVoxels << " voxels of "
           << tree_->getResolution() << " (an occupied leaf at depth " << it.getDepth() << " covers "
           << (std::uint64_t(1) << (3 * (kTreeDepth - it.getDepth()))) << "); too many to cluster";
      throw Error(what.str());
    }
  }
  std::vector<Entry> entries;
  entries.reserve(total);
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
    if (!tree_->isNodeOccupied(*it)) continue;
    const float log_odds = it->getLogOdds();
    const unsigned depth = it.getDepth();
    const octomap::OcTreeKey key = it.getKey();
    if (depth == kTreeDepth) {
      entries.push_back({key, log_odds});
      continue;
    }
    // A pruned leaf: every finest-level key below it.
    const unsigned size = 1u << (kTreeDepth - depth);
    const unsigned base[3] = {key[0] & ~(size - 1), key[1] & ~(size - 1), key[2] & ~(size - 1)};
    for (unsigned x = 0; x < size; ++x) {
      for (unsigned y = 0; y < size; ++y) {
        for (unsigned z = 0; z < size; ++z) {
          entries.push_back({octomap::OcTreeKey(static_cast<octomap::key_type>(base[0] + x),
                                                static_cast<octomap::key_type>(base[1] + y),
                                                static_cast<octomap::key_type>(base[2] + z)),
                             log_odds});
        }
      }
    }
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return lessKey(a.key, b.key); });
  std::vector<OccupiedVoxel> voxels;
  voxels.reserve(entries.size());
  for (const Entry& e : entries) {
    OccupiedVoxel v;
    v.center = Eigen::Vector3d(tree_->keyToCoord(e.key[0]), tree_->keyToCoord(e.key[1]), tree_->keyToCoord(e.key[2]));
    const auto count = point_counts_.find(e.key);
    v.weight = count == point_counts_.end() ? 1 : count->second;
    v.log_odds = e.log_odds;
    voxels.push_back(v);
  }
  return voxels;
}

bool addressable(const octomap::OcTree& tree, const io::Point& p) {
  const detail::KeyCaster caster(tree);
  int key[3];
  return caster.coordToKeyChecked(toPoint3d(p), key);
}

struct PointMapBuilder::State {
  explicit State(const OctreeParams& p) : params(p), map(p), caster(map.tree()) {}

  // Pending codes are merged into the runs once they are as many as the runs (and at least this
  // many): a merge then costs about what making its codes cost, and at most half of what is held
  // is pending.
  static constexpr std::size_t kMinPending = std::size_t(1) << 14;

  void add(const io::Point* points, std::size_t n, io::InputStats& stats) {
    addDropped(stats, appendCodes(caster, points, n, pending, ok));
    if (pending.size() >= std::max(runs.size(), kMinPending)) merge();
  }

  void merge() {
    detail::sortUpdates(pending);
    collapseRuns(pending);
    merged.resize(runs.size() + pending.size());
    std::size_t a = 0, b = 0, out = 0;
    while (a < runs.size() && b < pending.size()) {
      if (runs[a].code < pending[b].code) {
        merged[out++] = runs[a++];
      } else if (pending[b].code < runs[a].code) {
        merged[out++] = pending[b++];
      } else {
        merged[out++] = {runs[a].code, runs[a].count + pending[b].count};
        ++a;
        ++b;
      }
    }
    while (a < runs.size()) merged[out++] = runs[a++];
    while (b < pending.size()) merged[out++] = pending[b++];
    merged.resize(out);
    runs.swap(merged);
    pending.clear();
    merged.clear();
  }

  OctreeParams params;
  OccupancyMap map;
  detail::KeyCaster caster;
  std::vector<detail::VoxelUpdate> runs;     // sorted by code, one per voxel, counts summed
  std::vector<detail::VoxelUpdate> pending;  // codes of points not merged yet
  std::vector<detail::VoxelUpdate> merged;   // merge target
  std::vector<char> ok;
};

PointMapBuilder::PointMapBuilder(const OctreeParams& params) : state_(std::make_unique<State>(params)) {}
PointMapBuilder::~PointMapBuilder() = default;
PointMapBuilder::PointMapBuilder(PointMapBuilder&&) noexcept = default;
PointMapBuilder& PointMapBuilder::operator=(PointMapBuilder&&) noexcept = default;

void PointMapBuilder::add(const io::Points& points, io::InputStats& stats) {
  state_->add(points.data(), points.size(), stats);
}

OccupancyMap PointMapBuilder::finish() {
  if (!state_->pending.empty()) state_->merge();
  OccupancyMap map = std::move(state_->map);
  recordCounts(map, state_->runs);
  detail::applyUpdates(map.tree(), state_->runs);
  state_ = std::make_unique<State>(state_->params);
  return map;
}

OccupancyMap buildFromPoints(const io::Points& points, const OctreeParams& params, io::InputStats& stats) {
  PointMapBuilder builder(params);
  // In slices: the keys of one slice at a time, not of all points, are held besides the runs.
  const std::size_t slice = std::size_t(1) << 20;
  for (std::size_t first = 0; first < points.size(); first += slice) {
    builder.state_->add(points.data() + first, std::min(slice, points.size() - first), stats);
  }
  return builder.finish();
}

OccupancyMap buildWithTrajectory(const io::Points& points, const std::vector<io::Keyframe>& keyframes,
                                 const OctreeParams& params, io::InputStats& stats) {
  if (keyframes.empty()) throw Error::inParameter("keyframes", "none to cast free space from");
  OccupancyMap map(params);
  std::size_t dropped = 0;
  std::vector<char> ok;
  recordCounts(map, countPoints(map.tree(), points, ok, dropped));
  addDropped(stats, dropped);

  const detail::KeyframeIndex index(keyframes);
  std::vector<std::uint32_t> owner(points.size());
  tbb::parallel_for(std::size_t{0}, points.size(), std::size_t{4096}, [&](std::size_t begin) {
    const std::size_t end = std::min(points.size(), begin + 4096);
    for (std::size_t i = begin; i < end; ++i) {
      owner[i] = ok[i] ? static_cast<std::uint32_t>(index.lookup(points[i])) : 0;
    }
  });
  // Counting sort by keyframe, keeping the input order within each group.
  std::vector<std::size_t> start(keyframes.size() + 1, 0);
  for (std::size_t i = 0; i < points.size(); ++i) start[owner[i] + 1] += ok[i];
  for (std::size_t k = 0; k < keyframes.size(); ++k) start[k + 1] += start[k];
  io::Points grouped(start.back());
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (ok[i]) grouped[next[owner[i]]++] = points[i];
  }
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    if (start[k] == start[k + 1]) continue;
    const io::Points scan(grouped.begin() + static_cast<std::ptrdiff_t>(start[k]),
                          grouped.begin() + static_cast<std::ptrdiff_t>(start[k + 1]));
    insertScan(map.tree(), scan, keyframes[k].position, params.max_range);
  }
  return map;
}

OccupancyMap buildFromScan(const io::Points& points, const io::Point& origin, const OctreeParams& params,
                           io::InputStats& stats) {
  OccupancyMap map(params);
  std::size_t dropped = 0;
  std::vector<char> ok;
  recordCounts(map, countPoints(map.tree(), points, ok, dropped));
  addDropped(stats, dropped);
  io::Points addressable;
  addressable.reserve(points.size() - dropped);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (ok[i]) addressable.push_back(points[i]);
  }
  insertScan(map.tree(), addressable, origin, params.max_range);
  return map;
}

OccupancyMap readMap(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open octree file");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(path + ": read error");
  const bool full = bytes.rfind("# Octomap OcTree file", 0) == 0;
  const bool binary = bytes.rfind("# Octomap OcTree binary file", 0) == 0;
  if (!full && !binary) throw Error(path + ": not an OctoMap file (no '# Octomap OcTree' header)");
  // octomap trusts the node stream: a truncated or corrupt one reads uninitialised bytes and can
  // recurse without end. Walk it first, then give octomap those node bytes alone (its readData and
  // readBinaryData are what AbstractOcTree::read and readBinary call after their own header parse).
  const detail::OctreeFileHeader header = detail::validateOctreeFile(path, bytes, binary);  // id is OcTree
  OctreeParams params;
  params.resolution = header.resolution;
  OccupancyMap map(params);
  if (header.size > 0) {
    std::istringstream nodes(bytes.substr(header.data_offset));
    if (binary) {
      map.tree().readBinaryData(nodes);
    } else {
      map.tree().readData(nodes);
    }
  }
  if (map.tree().size() != header.size)
    throw Error(path + ": octomap read " + std::to_string(map.tree().size()) + " nodes, the header says " +
                std::to_string(header.size));
  return map;
}

void writeMap(const OccupancyMap& map, const std::string& path) {
  const std::string ext = extensionOf(path);
  if (ext != "bt" && ext != "ot") throw Error(path + ": octree file must end in .bt or .ot");
  core::writeFileAtomically(
      path,
      [&map, &ext, &path](std::ostream& out) {
        const bool ok = ext == "bt" ? writeBinaryQuietly(map.tree(), out) : map.tree().write(out);
        if (!ok) throw Error(path + ": octomap could not write the tree");
      },
      true);
}

MapInfo describe(const octomap::OcTree& tree) {
  MapInfo info;
  info.resolution = tree.getResolution();
  if (tree.getRoot() != nullptr) {
    double x, y, z;
    tree.getMetricMin(x, y, z);
    info.min = Eigen::Vector3d(x, y, z);
    tree.getMetricMax(x, y, z);
    info.max = Eigen::Vector3d(x, y, z);
  }
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (tree.isNodeOccupied(*it))
      ++info.occupied_leaves;
    else
      ++info.free_leaves;
  }
  info.nodes = tree.size();
  info.memory_bytes = tree.memoryUsage();
  return info;
}

}  // namespace hullmap::mapper
