#include "hullmap/core/warning.hpp"

#include <charconv>
#include <cstdint>
#include <cstdio>

namespace hullmap {
namespace {

/// A length or radius as the shortest text that reads back to it (0.05, not 0.050000000000000003).
std::string shortest(double value) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

/// A count (held as a double, exact below 2^53).
std::string count(double value) { return std::to_string(std::uint64_t(value)); }

/// printf-style text of at most 400 characters.
template <typename... Args>
std::string printed(const char* format, Args... args) {
  char buffer[400];
  std::snprintf(buffer, sizeof buffer, format, args...);
  return buffer;
}

/// "51%": part of whole, rounded.
std::string percent(double part, double whole) { return printed("%.0f%%", 100.0 * part / whole); }

}  // namespace

double Warning::number(std::string_view name) const {
  for (const auto& [n, value] : numbers)
    if (n == name) return value;
  return 0.0;
}

std::string fieldSpelling(std::string_view field, std::string_view value) {
  std::string out(field);
  if (!value.empty()) out.append("=").append(value);
  return out;
}

const char* warningName(Warning::Code code) {
  switch (code) {
    case Warning::Code::kEpsBelowResolution:
      return "eps_below_resolution";
    case Warning::Code::kEpsBelowResolutionInColumns:
      return "eps_below_resolution_in_columns";
    case Warning::Code::kNoObstacle:
      return "no_obstacle";
    case Warning::Code::kMostlyNoise:
      return "mostly_noise";
    case Warning::Code::kKeptFloorTilted:
      return "kept_floor_tilted";
    case Warning::Code::kMapLooksTilted:
      return "map_looks_tilted";
    case Warning::Code::kOrbSlamFrame:
      return "orbslam_frame";
    case Warning::Code::kCheckNoObstacle:
      return "check_no_obstacle";
    case Warning::Code::kCheckMostlyNoise:
      return "check_mostly_noise";
    case Warning::Code::kSparseForResolution:
      return "sparse_for_resolution";
  }
  return "unknown";
}

std::string warningText(const Warning& w, const ParameterSpelling& spell) {
  const auto name = [&](std::string_view field) { return spell(field, ""); };
  const std::string larger_eps = "a larger " + name("eps") + " or a smaller " + name("min_pts");
  const std::string slanted =
      "heights, " + name("z_min") + "/" + name("z_max") + " and footprints are slanted by as much";
  switch (w.code) {
    case Warning::Code::kEpsBelowResolution:
    case Warning::Code::kEpsBelowResolutionInColumns: {
      const std::string resolution = shortest(w.number("resolution"));
      return spell("eps", shortest(w.number("eps"))) + " is below the octree resolution " + resolution +
             (w.code == Warning::Code::kEpsBelowResolution
                  ? ": no two voxels are neighbours, so every voxel stands alone (a cluster only when it holds " +
                        name("min_pts") + " points itself); use "
                  : std::string(": only voxels in one vertical column are neighbours; use ")) +
             name("eps") + " >= " + resolution + ", or a finer " + name("resolution");
    }
    case Warning::Code::kNoObstacle:
      return "no obstacle: all " + count(w.number("occupied_voxels")) + " occupied voxels are noise to DBSCAN (" +
             spell("eps", shortest(w.number("eps"))) + ", " + spell("min_pts", count(w.number("min_pts"))) +
             "), so every path checks clear against the hulls; try " + larger_eps + ", or check paths with " +
             spell("against", "octree");
    case Warning::Code::kMostlyNoise: {
      const double noise = w.number("noise_voxels"), occupied = w.number("occupied_voxels");
      return percent(noise, occupied) + " of the occupied voxels (" + count(noise) + " of " + count(occupied) +
             ") are noise and in no obstacle; path checks against the hulls do not see them; try " + larger_eps +
             ", or check paths with " + spell("against", "octree");
    }
    case Warning::Code::kKeptFloorTilted:
      return printed(
                 "the floor found (%.0f%% of the points) is %.1f degrees from level, and the map was kept in "
                 "its input frame: ",
                 100.0 * w.number("inlier_share"), w.number("tilt_deg")) +
             slanted + "; " + spell("level", "on") + " levels it";
    case Warning::Code::kMapLooksTilted:
      return printed(
                 "the map's main floor-like plane (%.0f%% of the occupied voxels) is %.1f degrees from level "
                 "after ",
                 100.0 * w.number("inlier_share"), w.number("tilt_deg")) +
             spell("up", w.subject) +
             ": if it is the floor, the map is tilted (SLAM maps start in the first camera's frame), and " + slanted;
    case Warning::Code::kOrbSlamFrame:
      return w.subject +
             " looks like ORB-SLAM output, whose frame is the first camera's (x right, y down, z forward): it "
             "likely needs " +
             spell("up", "-y") + " (" + name("up") + " was left at z)";
    case Warning::Code::kCheckNoObstacle: {
      std::string what = "the build has no obstacle";
      if (w.number("occupied_voxels") > 0)
        what += " although " + count(w.number("occupied_voxels")) + " voxels are occupied (all noise to DBSCAN)";
      return what + ": every path is clear against the hulls; check with " + spell("against", "octree") +
             ", or rebuild with " + larger_eps;
    }
    case Warning::Code::kCheckMostlyNoise: {
      const double noise = w.number("noise_voxels"), occupied = w.number("occupied_voxels");
      return percent(noise, occupied) + " of the build's occupied voxels (" + count(noise) + " of " + count(occupied) +
             ") are noise and in no hull, so this check does not see them; check with " + spell("against", "octree") +
             ", or rebuild with " + larger_eps;
    }
    case Warning::Code::kSparseForResolution: {
      const double resolution = w.number("resolution"), spacing = w.number("spacing");
      return printed("the map's points lie about %.3g apart (%.0f voxels at ", spacing, spacing / resolution) +
             spell("resolution", shortest(resolution)) +
             "; three in four occupied voxels have their 4th nearest within it): its surfaces fall "
             "apart into lone voxels and noise; try " +
             spell("resolution", shortest(w.number("suggested")));
    }
  }
  return warningName(w.code);
}

}  // namespace hullmap
