#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hullmap/io/point_cloud.hpp"

namespace hullmap::mapper {

/// A plane {x : normal . x = offset}, map frame and map units. `normal` is a unit vector pointing
/// into the map: up for a floor, down for a ceiling. signedDistance > 0 is the map's side.
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;

  double signedDistance(const Eigen::Vector3d& p) const { return normal.dot(p) - offset; }
};

/// Which bounding plane to look for: the floor is under the map (nearly all points above it), the
/// ceiling over it (nearly all points below it).
enum class PlaneSide { kFloor, kCeiling };

/// How findBoundingPlane searches and when it accepts a plane.
///
/// The search is RANSAC (a fixed seed: same points, same plane, on every machine) over planes within
/// `max_tilt_deg` of the up hint with at most `max_beyond_share` of the points beyond them; the one
/// with the most points within `band` wins and is refined by least squares on its inliers (sample
/// sizes and why the floor beats a table top: docs/DESIGN_NOTES.md, "floor.hpp: the search").
///
/// Acceptance (a map without floor is normal; the result then says why none was taken):
/// - inlier share >= `min_inlier_share` of the points;
/// - far-side share <= `max_beyond_share`;
/// - coverage >= `min_coverage`: project the points onto the plane, on a grid of cells of
///   `coverage_cell` map units (0: 10 * band), over the box holding the central 98% of the points
///   along each plane axis; coverage = cells holding an inlier / cells holding any point. A floor
///   spreads under the whole map (docs/DESIGN_NOTES.md, "floor.hpp: coverage").
/// - tilt <= `max_tilt_deg`.
struct PlaneSearchParams {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  ///< up hint (the map frame's z after --up)
  double band = 0.05;                             ///< inlier distance, map units (about the voxel size)
  bool fit_tilt = true;        ///< false: the normal is `up` exactly, only the height is found (--align)
  double max_tilt_deg = 30.0;  ///< largest angle between the plane normal and up
  double min_inlier_share = 0.03;
  double max_beyond_share = 0.05;
  /// coverage a floor needs, in [0, 1] (why 0.3: docs/DESIGN_NOTES.md, "floor.hpp: coverage")
  double min_coverage = 0.3;
  double coverage_cell = 0.0;  ///< map units; 0: 10 * band
  int iterations = 1000;       ///< RANSAC draws
  std::size_t sample_points = 20000;
  std::uint64_t seed = 1;
};

/// What findBoundingPlane found.
struct PlaneFit {
  bool found = false;       ///< the best candidate met every acceptance rule
  std::string reason;       ///< when not found: which rule failed (or "no candidate")
  Plane plane;              ///< the best candidate (meaningful when found, informative otherwise)
  double tilt_deg = 0.0;    ///< angle between plane normal and the up hint
  std::size_t inliers = 0;  ///< points within band (all points, not the sample)
  double inlier_share = 0.0;
  double beyond_share = 0.0;  ///< points more than band on the far side
  double coverage = 0.0;
};

/// Finds the floor (or ceiling) of a map: see PlaneSearchParams. Points in the map frame, map
/// units: map points, a sample of them, or occupied voxel centres (then band >= the voxel size).
/// Cost: iterations x sample_points distance tests, plus two passes over the points. Throws
/// hullmap::Error naming --floor on a band <= 0, non-finite parameters or points, or a zero up
/// hint. Fewer than 3 points give found = false. Thread-safe (no shared state).
PlaneFit findBoundingPlane(const io::Points& points, PlaneSide side, const PlaneSearchParams& params = {});

/// The rigid transform that levels a floor: rotates its normal onto +z by the smallest rotation and
/// moves the plane to z = 0. Apply it to points and keyframes (as Isometry3d: x -> R x + t).
Eigen::Isometry3d levelingTransform(const Plane& floor);

/// The horizontal plane z = height, facing up (floor) or down (ceiling): an explicit `--floor Z`.
Plane horizontalPlane(double height, PlaneSide side);

/// `--floor` / `--ceiling`: auto (search), none, or an explicit height Z in the map frame.
struct PlaneSetting {
  enum class Mode { kAuto, kNone, kHeight } mode = Mode::kAuto;
  double height = 0.0;  ///< map frame z, for kHeight
};

/// Parses "auto", "none" or a finite number. Throws hullmap::Error naming `option` and the text.
PlaneSetting parsePlaneSetting(const std::string& option, const std::string& text);

/// What a voxel is for clustering.
enum class SurfaceClass : std::uint8_t { kObstacle = 0, kFloor = 1, kCeiling = 2 };

/// Classifies occupied voxel centres: kFloor when at most `band` above the floor (below it
/// included: nothing under the floor is an obstacle), kCeiling likewise under the ceiling (floor
/// wins where both apply), else kObstacle. Floor and ceiling voxels stay in the map; they are
/// left out of clustering. `band` (map units) should cover the plane's noise plus half a voxel
/// diagonal. Throws hullmap::Error naming --floor on band < 0 or non-finite.
std::vector<SurfaceClass> classifySurfaces(const std::vector<Eigen::Vector3d>& centres,
                                           const std::optional<Plane>& floor, const std::optional<Plane>& ceiling,
                                           double band);

}  // namespace hullmap::mapper
