#pragma once
// Private to hullmap_pipeline: the ground of a map that no floor plane explains (ground.cpp).

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/mapper/floor.hpp"
#include "hullmap/mapper/terrain.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {

/// The ground found: its solid for the checks, and what the report says of it.
struct Ground {
  collision::Surface surface;  ///< "ground", a height field
  GroundReport report;         ///< voxels still 0: the clustering stage counts them
  std::vector<char> measured;  ///< per node (x fastest): 1 when its height was measured as ground
};

/// Whether `floor` explains the ground fitted: fewer than kPlaneMissShare of the measured ground
/// nodes that speak of the floor lie farther than 2 * initial_threshold (vertically) from the plane.
/// Nodes below that band speak of it; so do nodes above it that rise from the band's nodes no faster
/// than params.slope (a street's slope). A node higher than that stands on the floor (a wall or a
/// car whose foot was not seen), and is left out. A street's slopes and bumps, or a monocular map
/// bent by scale drift, do not lie on one plane however wide its band.
bool planeExplainsGround(const mapper::Plane& floor, const Ground& ground, const mapper::TerrainParams& params);

/// The share of the measured ground nodes off the floor plane above which the plane does not
/// explain the ground.
inline constexpr double kPlaneMissShare = 0.25;

/// Fits the ground under `points` (map frame; the build's sample of its points) with
/// mapper::fitTerrain and `params` under the keyframes. The fit follows each cell's lowest point;
/// the ground runs through the middle of its points: each node is raised by the median height over
/// the fit of the points within params.initial_threshold above it in the four cells around the node
/// (never lowered), then held params.keyframe_clearance under the keyframes. nullopt when no ground
/// explains the map: fewer than kGroundMinShare of the points within initial_threshold of the fit,
/// fewer than 4 ground cells, or points the filter finds no ground in (fitTerrain's errors other
/// than a bad setting, which it throws).
std::optional<Ground> fitGround(const std::vector<Eigen::Vector3d>& points,
                                const std::vector<Eigen::Vector3d>& keyframes, const mapper::TerrainParams& params);

/// The height above the ground within which an occupied voxel's centre is the ground's: half a
/// voxel (a voxel holding a point on the surface has its centre that far from it at most) and half
/// of params.initial_threshold (the points' spread about the surface).
double groundBand(const mapper::TerrainParams& params, double resolution);

/// The build's ground stage (BuildParams::ground, terrain): when `floor` is kAuto and the map was
/// not levelled (a levelled map is a camera's frame, not metric), fits the ground to the build's
/// `sample` of its points (map frame) under the keyframes, the same in both paths (whole,
/// streamed); a floor plane found gives way to it when it does not explain it (planeExplainsGround:
/// PlaneReport::ground_instead). Records BuildReport::ground and adds the surface to
/// result.surfaces.
void recordGround(const BuildParams& params, const io::Points& sample, const std::vector<io::Keyframe>& keyframes,
                  BuildResult& result);

}  // namespace hullmap::pipeline
