// The floor and ceiling of a build: their voxels' rims joined to the clusters standing on them, their
// solid half-spaces for path checks, the free voxels for the parts' count, and one floor height for
// closing shells.
#include "surfaces.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/detail/test_hooks.hpp"

namespace hullmap::pipeline {

namespace detail {

void attachSurfaceRims(const std::vector<Eigen::Vector3d>& centers, double resolution, double reach,
                       std::vector<std::int32_t>& labels) {
  if (centers.size() != labels.size()) throw Error::inParameter("labels", "one label per voxel centre expected");
  // Lattice cells: centres lie at (k + 1/2) * resolution, so floor() gives k without ties.
  const auto cell = [&](double v) { return static_cast<std::int64_t>(std::floor(v / resolution)); };
  const auto columnKey = [](std::int64_t i, std::int64_t j) {
    return static_cast<std::uint64_t>(i + (std::int64_t(1) << 31)) << 32 |
           (static_cast<std::uint64_t>(j + (std::int64_t(1) << 31)) & 0xffffffffu);
  };
  const std::int64_t layers = static_cast<std::int64_t>(std::floor(std::max(2.0, reach / resolution) + 1e-9));
  // The reach in whole cells (lattice distances are compared squared, in cells^2).
  const double reach_cells = std::max(reach / resolution, 0.0);
  const double reach2 = reach_cells * reach_cells + 1e-9;
  const std::int64_t span = static_cast<std::int64_t>(std::floor(reach_cells + 1e-9));
  // The clustered voxels of each column, by layer.
  using Column = std::vector<std::pair<std::int64_t, std::int32_t>>;
  std::unordered_map<std::uint64_t, Column> columns;
  for (std::size_t i = 0; i < centers.size(); ++i)
    if (labels[i] >= 0)
      columns[columnKey(cell(centers[i].x()), cell(centers[i].y()))].emplace_back(cell(centers[i].z()), labels[i]);
  for (auto& [key, column] : columns) std::sort(column.begin(), column.end());
  // Calls f(layer, label) for the clustered voxels of column (i, j) with layers in [lo, hi], in
  // order, until f returns true; returns whether it did.
  const auto scan = [&](std::int64_t i, std::int64_t j, std::int64_t lo, std::int64_t hi, auto&& f) {
    const auto hit = columns.find(columnKey(i, j));
    if (hit == columns.end() || lo > hi) return false;
    const Column& column = hit->second;
    for (auto it = std::lower_bound(column.begin(), column.end(), std::make_pair(lo, std::int32_t(-1)));
         it != column.end() && it->first <= hi; ++it)
      if (f(it->first, it->second)) return true;
    return false;
  };
  // Whether the clustered voxel of `label` at (i, j, k) is the near end of a face of its cluster
  // that stands on the surface (sign +1, a floor) or hangs from it (-1, a ceiling): its cluster has
  // two voxels within `reach` of it (centre distance) at least 2 layers farther from the surface. One
  // is not enough: a lone stray voxel (an outlier DBSCAN took in) above a table top is no face.
  std::unordered_map<std::uint64_t, std::unordered_map<std::int64_t, bool>> face_memo[2];  // floor, ceiling
  const auto onFace = [&](std::int64_t i, std::int64_t j, std::int64_t k, std::int32_t label, std::int64_t sign) {
    auto& memo = face_memo[sign > 0 ? 0 : 1][columnKey(i, j)];
    if (const auto found = memo.find(k); found != memo.end()) return found->second;
    const std::int64_t lo = sign > 0 ? k + 2 : k - span, hi = sign > 0 ? k + span : k - 2;
    int evidence = 0;
    for (std::int64_t di = -span; di <= span && evidence < 2; ++di)
      for (std::int64_t dj = -span; dj <= span && evidence < 2; ++dj) {
        if (double(di * di + dj * dj) > reach2) continue;
        scan(i + di, j + dj, lo, hi, [&](std::int64_t layer, std::int32_t l) {
          const std::int64_t dk = layer - k;
          if (l == label && double(di * di + dj * dj + dk * dk) <= reach2) ++evidence;
          return evidence >= 2;
        });
      }
    return memo[k] = evidence >= 2;
  };
  struct Candidate {
    std::int64_t distance;  ///< squared lattice distance to the surface voxel
    std::int32_t label;
    std::int64_t i, j, k;
    bool operator<(const Candidate& o) const { return std::tie(distance, label) < std::tie(o.distance, o.label); }
  };
  std::vector<std::pair<std::size_t, std::int32_t>> joins;
  std::vector<Candidate> candidates;
  for (std::size_t v = 0; v < centers.size(); ++v) {
    if (labels[v] != kFloorLabel && labels[v] != kCeilingLabel) continue;
    const std::int64_t sign = labels[v] == kFloorLabel ? 1 : -1;
    const std::int64_t ci = cell(centers[v].x()), cj = cell(centers[v].y()), ck = cell(centers[v].z());
    // Layers from the surface voxel's on its far side (a floor's: its layer and above; a ceiling's:
    // its layer and below), up to n.
    const auto lo = [&](std::int64_t n) { return sign > 0 ? ck : ck - n; };
    const auto hi = [&](std::int64_t n) { return sign > 0 ? ck + n : ck; };
    // 1 and 2: the clustered voxels of the 3 x 3 columns on the far side within 2 * layers, nearest
    // first. Within `layers` the nearest joins (2 + layers^2 < (layers + 1)^2: these come first);
    // farther, the nearest that is the near end of a face.
    candidates.clear();
    for (std::int64_t di = -1; di <= 1; ++di)
      for (std::int64_t dj = -1; dj <= 1; ++dj)
        scan(ci + di, cj + dj, lo(2 * layers), hi(2 * layers), [&](std::int64_t layer, std::int32_t l) {
          const std::int64_t dk = layer - ck;
          candidates.push_back({di * di + dj * dj + dk * dk, l, ci + di, cj + dj, layer});
          return false;
        });
    std::sort(candidates.begin(), candidates.end());
    for (const Candidate& c : candidates)
      if (std::abs(c.k - ck) <= layers || onFace(c.i, c.j, c.k, c.label, sign)) {
        joins.emplace_back(v, c.label);
        break;
      }
  }
  for (const auto& [v, label] : joins) labels[v] = label;
}

}  // namespace detail

/// Centres of the observed-free leaves of the map (each pruned leaf once).
std::vector<Eigen::Vector3d> freeVoxelCentres(const mapper::OccupancyMap& map) {
  std::vector<Eigen::Vector3d> free;
  const auto& tree = map.tree();
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (tree.isNodeOccupied(*it)) continue;
    const auto c = it.getCoordinate();
    free.emplace_back(c.x(), c.y(), c.z());
  }
  return free;
}

/// The floor and ceiling as solid half-spaces: up to the plane, or to the far face of the highest
/// voxel set aside as that surface when it lies beyond (the voxels lie inside completely).
std::vector<collision::Surface> boundingSurfaces(const BuildReport& report, const std::vector<Eigen::Vector3d>& centers,
                                                 const std::vector<std::int32_t>& labels, double resolution) {
  std::vector<collision::Surface> out;
  const auto add = [&](const PlaneReport& surface, std::int32_t label, const char* name) {
    if (!surface.plane) return;
    const double norm = surface.plane->normal.norm();
    collision::Surface h = collision::Surface::plane(name, surface.plane->normal / norm, surface.plane->offset / norm);
    // The support of a voxel cube along the normal, beyond its centre.
    const double half = 0.5 * resolution * h.normal.cwiseAbs().sum();
    for (std::size_t i = 0; i < centers.size(); ++i)
      if (labels[i] == label) h.offset = std::max(h.offset, h.normal.dot(centers[i]) + half);
    out.push_back(std::move(h));
  };
  add(report.floor, kFloorLabel, "floor");
  add(report.ceiling, kCeilingLabel, "ceiling");
  return out;
}

/// The floor's height for closing shells from below, when one height serves the whole map: the
/// plane's height under the voxels' middle when its tilt moves it by at most a voxel across them
/// (a levelled or aligned floor is exactly level).
std::optional<double> levelFloorHeight(const mapper::Plane& floor, const std::vector<Eigen::Vector3d>& centers,
                                       double resolution) {
  const Eigen::Vector3d& n = floor.normal;
  if (!(std::abs(n.z()) > 0.99) || centers.empty()) return std::nullopt;
  Eigen::AlignedBox2d box;
  for (const auto& c : centers) box.extend(c.head<2>());
  const Eigen::Vector2d middle = box.center();
  const double rise = n.head<2>().norm() / std::abs(n.z()) * 0.5 * box.diagonal().norm();
  if (rise > resolution) return std::nullopt;
  return (floor.offset - n.x() * middle.x() - n.y() * middle.y()) / n.z();
}

}  // namespace hullmap::pipeline
