#pragma once
// The ground of a map that one plane does not explain (outdoors: slopes, bumps, monocular scale
// drift): a 2.5D height field fitted with the progressive morphological filter (Zhang, Chen,
// Whitman, Shyu, Yan and Zhang, "A progressive morphological filter for removing nonground
// measurements from airborne LIDAR data", IEEE TGRS 41(4), 2003), then kept under the camera's
// keyframes.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "hullmap/core/height_field.hpp"

namespace hullmap::mapper {

/// Settings of fitTerrain (map units unless said).
struct TerrainParams {
  double cell = 2.0;                ///< grid cell side, > 0: a few points per cell (a monocular outdoor map: about 2 m)
  double max_object = 24.0;         ///< widest non-ground object the filter removes (buildings), > 0
  double slope = 0.15;              ///< steepest ground the filter keeps, rise per run, >= 0 (streets: up to about 0.1)
  double initial_threshold = 0.3;   ///< height above the opened surface that is still ground at the first window
  double max_threshold = 3.0;       ///< the same at any window, >= initial_threshold
  double low_share = 0.0;           ///< a cell's height: its points' k-th lowest z, k = 1 + floor(low_share * count)
  double keyframe_clearance = 0.3;  ///< the ground stays at least this below every keyframe over it, >= 0
  int min_support = 3;              ///< a cell's height needs this many points within initial_threshold over it, >= 1
};

/// What fitTerrain found.
struct Terrain {
  HeightField surface;
  std::vector<char> ground;  ///< per cell (x fastest): 1 when the cell's low point is ground
  std::size_t cells_with_points = 0;
  std::size_t ground_cells = 0;       ///< the heights measured; every other node is interpolated
  std::size_t unsupported_cells = 0;  ///< cells whose points were too few to measure a height (min_support)
  std::size_t lowered = 0;            ///< nodes lowered under a keyframe
};

/// Fits the ground under `points` (map frame, z up) on a grid over the bulk of the points: a low height
/// per cell, the progressive morphological filter, harmonic fill under the slope cone (boundBySlope),
/// nodes under keyframes lowered (keepUnderKeyframes). The steps: docs/DESIGN_NOTES.md, "terrain.hpp".
/// Deterministic. Throws hullmap::Error naming the TerrainParams field on a bad setting
/// (Error::parameter() is the field), and, with no parameter, on non-finite points or keyframes, an
/// input with no point, a grid of more than 100000 cells a side, or no cell of ground.
Terrain fitTerrain(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& keyframes,
                   const TerrainParams& params = {});

/// For every node not `measured` (per node, x fastest): the measured node m that minimises
/// h_m + slope * |node - m| (distances in map units), its support; SIZE_MAX at measured nodes, and
/// everywhere when no node is measured. Exact (a search in growing rings, stopped by the lowest
/// measured height).
std::vector<std::size_t> slopeSupport(const HeightField& field, const std::vector<char>& measured, double slope);

/// Lowers every node not `measured` to at most h_m + slope * |node - m| over its support m
/// (slopeSupport): no filled height rises above the seen ground by more than the slope allows over
/// the distance. Returns how many nodes were lowered.
std::size_t boundBySlope(HeightField& field, const std::vector<char>& measured, double slope);

/// fitTerrain's step 4 on its own: every node within 1.5 cells of a keyframe's (x, y) lowered to
/// keyframe z - clearance when above it. Returns how many nodes were lowered.
std::size_t keepUnderKeyframes(HeightField& field, const std::vector<Eigen::Vector3d>& keyframes, double clearance);

}  // namespace hullmap::mapper
