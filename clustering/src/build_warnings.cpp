#include "hullmap/clustering/build_warnings.hpp"

#include <charconv>
#include <cstdio>

namespace hullmap::clustering {
namespace {

std::string numberText(double value) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

std::string percent(std::size_t part, std::size_t whole) {
  const double share = 100.0 * double(part) / double(whole);
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.0f%%", share);
  return buffer;
}

bool mostlyNoise(const ClusteringOutcome& o) {
  return o.occupied_voxels > 0 && double(o.noise_voxels) > kNoiseShareLimit * double(o.occupied_voxels);
}

}  // namespace

std::vector<std::string> buildWarnings(const ClusteringOutcome& o) {
  std::vector<std::string> warnings;
  if (o.resolution > 0.0 && o.eps < o.resolution) {
    warnings.push_back("--eps " + numberText(o.eps) + " is below the octree resolution " + numberText(o.resolution) +
                       (o.metric == Metric::kXyz
                            ? ": no two voxels are neighbours, so every voxel stands alone (a cluster only when it "
                              "holds --min-pts points itself); use --eps >= "
                            : ": only voxels in one vertical column are neighbours; use --eps >= ") +
                       numberText(o.resolution) + ", or a finer --resolution");
  }
  if (o.obstacles == 0 && o.occupied_voxels > 0) {
    warnings.push_back("no obstacle: all " + std::to_string(o.occupied_voxels) +
                       " occupied voxels are noise to DBSCAN (--eps " + numberText(o.eps) + ", --min-pts " +
                       std::to_string(o.min_pts) +
                       "), so every path checks clear against the hulls; try a larger --eps or a smaller "
                       "--min-pts, or check paths with --against octree");
  } else if (mostlyNoise(o)) {
    warnings.push_back(percent(o.noise_voxels, o.occupied_voxels) + " of the occupied voxels (" +
                       std::to_string(o.noise_voxels) + " of " + std::to_string(o.occupied_voxels) +
                       ") are noise and in no obstacle; path checks against the hulls do not see them; try a "
                       "larger --eps or a smaller --min-pts, or check paths with --against octree");
  }
  return warnings;
}

std::vector<std::string> hullCheckWarnings(const ClusteringOutcome& o) {
  std::vector<std::string> warnings;
  if (o.obstacles == 0) {
    std::string what = "the build has no obstacle";
    if (o.occupied_voxels > 0)
      what += " although " + std::to_string(o.occupied_voxels) + " voxels are occupied (all noise to DBSCAN)";
    warnings.push_back(what +
                       ": every path is clear against the hulls; check with --against octree, or rebuild with a "
                       "larger --eps or a smaller --min-pts");
  } else if (mostlyNoise(o)) {
    warnings.push_back(percent(o.noise_voxels, o.occupied_voxels) + " of the build's occupied voxels (" +
                       std::to_string(o.noise_voxels) + " of " + std::to_string(o.occupied_voxels) +
                       ") are noise and in no hull, so this check does not see them; check with --against "
                       "octree, or rebuild with a larger --eps or a smaller --min-pts");
  }
  return warnings;
}

}  // namespace hullmap::clustering
