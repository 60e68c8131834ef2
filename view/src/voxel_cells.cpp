#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "hullmap/core/error.hpp"
#include "hullmap/view/html_view.hpp"

namespace hullmap::view {
namespace {

// Octree keys are 16 bits an axis: no map spans more voxels than this on an axis.
constexpr std::int64_t kMaxSpan = std::int64_t(1) << 16;

// Priority of a label when voxels of several labels share a cell: obstacles first, then noise,
// floor or ground, ceiling (any other negative label last).
int rank(std::int32_t label) {
  if (label >= 0) return 0;
  if (label == -4) return 2;  // the ground (pipeline::kGroundLabel), as the floor
  if (label >= -3) return -label;
  return 4;
}

}  // namespace

namespace {

// Voxels on their lattice: integer indices from the smallest on each axis.
struct Lattice {
  std::vector<std::array<std::int64_t, 3>> index;
  std::array<std::int64_t, 3> lo{};
  std::uint64_t key(std::size_t i, std::int64_t factor) const {
    const auto& k = index[i];
    return static_cast<std::uint64_t>((k[2] - lo[2]) / factor) << 32 |
           static_cast<std::uint64_t>((k[1] - lo[1]) / factor) << 16 |
           static_cast<std::uint64_t>((k[0] - lo[0]) / factor);
  }
};

Lattice lattice(const std::vector<Eigen::Vector3d>& centers, const std::vector<std::int32_t>& labels,
                double resolution) {
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    throw Error::inParameter("resolution", "must be a positive finite number");
  if (centers.size() != labels.size())
    throw Error("voxels: " + std::to_string(labels.size()) + " labels for " + std::to_string(centers.size()) +
                " centres");
  Lattice out;
  const std::size_t n = centers.size();
  out.index.resize(n);
  std::array<std::int64_t, 3> hi{};
  out.lo.fill(std::numeric_limits<std::int64_t>::max());
  hi.fill(std::numeric_limits<std::int64_t>::min());
  // A voxel's centre is (k + 1/2) * resolution.
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      const double k = centers[i][a] / resolution - 0.5;
      if (!std::isfinite(k) || std::abs(k) > 1e15)
        throw Error("voxels: centre " + std::to_string(i) + " is not a finite lattice position");
      out.index[i][a] = static_cast<std::int64_t>(std::llround(k));
      out.lo[a] = std::min(out.lo[a], out.index[i][a]);
      hi[a] = std::max(hi[a], out.index[i][a]);
    }
  }
  for (int a = 0; a < 3 && n > 0; ++a) {
    if (hi[a] - out.lo[a] >= kMaxSpan) {
      throw Error("voxels: the centres span " + std::to_string(hi[a] - out.lo[a] + 1) + " voxels along " +
                  std::string(1, "xyz"[a]) + ", more than an octree holds (65536)");
    }
  }
  return out;
}

std::size_t cellCount(const Lattice& l, std::int64_t factor) {
  std::vector<std::uint64_t> keys(l.index.size());
  for (std::size_t i = 0; i < keys.size(); ++i) keys[i] = l.key(i, factor);
  std::sort(keys.begin(), keys.end());
  return static_cast<std::size_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
}

// The cells of `factor`, each with the label its voxels give it.
VoxelCells cellsAt(const Lattice& l, const std::vector<std::int32_t>& labels, double resolution, std::int64_t factor) {
  VoxelCells out;
  out.factor = static_cast<int>(factor);
  out.cell = resolution * static_cast<double>(factor);
  const std::size_t n = l.index.size();
  std::vector<std::pair<std::uint64_t, std::int32_t>> members(n);
  for (std::size_t i = 0; i < n; ++i) members[i] = {l.key(i, factor), labels[i]};
  std::sort(members.begin(), members.end(), [](const auto& a, const auto& b) {
    if (a.first != b.first) return a.first < b.first;
    if (rank(a.second) != rank(b.second)) return rank(a.second) < rank(b.second);
    return a.second < b.second;
  });
  struct Cell {
    std::int32_t label;
    std::uint64_t key;
    std::size_t voxels;
  };
  std::vector<Cell> cells;
  for (std::size_t i = 0; i < n;) {
    std::size_t end = i;
    while (end < n && members[end].first == members[i].first) ++end;
    // Members are sorted by rank then label: the first run is the best class; within obstacles,
    // the longest run of one label wins (the first, i.e. the smallest id, on ties).
    std::int32_t best = members[i].second;
    std::size_t best_count = 0;
    for (std::size_t j = i; j < end && rank(members[j].second) == rank(members[i].second);) {
      std::size_t k = j;
      while (k < end && members[k].second == members[j].second) ++k;
      if (k - j > best_count) {
        best_count = k - j;
        best = members[j].second;
      }
      j = k;
    }
    cells.push_back({best, members[i].first, end - i});
    i = end;
  }
  std::sort(cells.begin(), cells.end(),
            [](const Cell& a, const Cell& b) { return a.label != b.label ? a.label < b.label : a.key < b.key; });
  const double f = static_cast<double>(factor);
  for (const Cell& c : cells) {
    const std::int64_t m[3] = {static_cast<std::int64_t>(c.key & 0xffff),
                               static_cast<std::int64_t>(c.key >> 16 & 0xffff),
                               static_cast<std::int64_t>(c.key >> 32 & 0xffff)};
    Eigen::Vector3d centre;
    for (int a = 0; a < 3; ++a)
      centre[a] = (static_cast<double>(l.lo[a]) + static_cast<double>(m[a]) * f + f / 2.0) * resolution;
    out.centers.push_back(centre);
    out.labels.push_back(c.label);
    out.voxels.push_back(c.voxels);
  }
  return out;
}

// The smallest power-of-two factor whose cells number at most `max_cells`.
std::int64_t fittingFactor(const Lattice& l, std::size_t max_cells) {
  std::int64_t factor = 1;
  while (factor < kMaxSpan && cellCount(l, factor) > max_cells) factor *= 2;
  return factor;
}

}  // namespace

VoxelCells mergeVoxelCells(const std::vector<Eigen::Vector3d>& centers, const std::vector<std::int32_t>& labels,
                           double resolution, std::size_t max_cells) {
  if (max_cells == 0) throw Error::inParameter("max_instances", "must be at least 1");
  const Lattice l = lattice(centers, labels, resolution);
  return cellsAt(l, labels, resolution, l.index.empty() ? 1 : fittingFactor(l, max_cells));
}

std::vector<VoxelCells> voxelLevels(const std::vector<Eigen::Vector3d>& centers,
                                    const std::vector<std::int32_t>& labels, double resolution, std::size_t max_cells,
                                    std::size_t coarsest_cells) {
  if (max_cells == 0) throw Error::inParameter("max_instances", "must be at least 1");
  const Lattice l = lattice(centers, labels, resolution);
  std::vector<VoxelCells> levels;
  std::int64_t factor = l.index.empty() ? 1 : fittingFactor(l, max_cells);
  levels.push_back(cellsAt(l, labels, resolution, factor));
  while (levels.back().centers.size() > coarsest_cells && factor < kMaxSpan) {
    factor *= 2;
    levels.push_back(cellsAt(l, labels, resolution, factor));
  }
  return levels;
}

}  // namespace hullmap::view
