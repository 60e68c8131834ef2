#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/sim/ground_truth.hpp"

namespace hullmap::sim {

/// Where evaluate() draws its random segments' endpoints.
/// - kFree: uniformly in the box of the truth grown by radius + clear_margin + 0.5, both keeping
///   radius + clear_margin from the truth (segments around the truth, outside a room's walls too).
/// - kInTruthBox: uniformly in the box of the truth itself, free or not (a room: anywhere inside its
///   walls, or in them), as a user draws test paths in the room: many are deep, and the clear ones
///   all lie inside the room.
/// - kCorridor: as kFree, and within corridor_width in (x, y) of the camera's path (`path`, the
///   keyframes in order) and at most corridor_height above the height of its nearest keyframe:
///   where a map gathered along that path can know the world (outdoors, the street: segments drawn
///   anywhere in a street's box cross the backs and roofs of buildings no camera saw).
/// All keep the endpoints radius + clear_margin above every true floor and below every ceiling, and
/// above every height field's surface where they are (at the point's (x, y) clamped to its grid).
enum class SegmentEnds { kFree, kInTruthBox, kCorridor };

/// Settings of evaluate(); every random draw comes from std::mt19937_64(seed) with hullmap's own
/// transforms, so the numbers are the same on every machine.
struct EvaluateParams {
  double radius = 0.3;  ///< drone radius R for the segment checks
  /// A map point is an observed point of the one shape whose surface is nearest (smallest |signed
  /// distance|, ties to the lower index) when that distance is at most this.
  double surface_margin = 0.05;
  double touch_margin = 0.1;  ///< a part touches a shape when part of its hull comes within this
  double far_margin = 0.1;    ///< swallowed volume: hull volume farther than this from every shape
  double depth_margin = 0.1;  ///< deep collision: the capsule penetrates a shape by more than this
  double clear_margin = 0.1;  ///< clear segment: keeps radius + this from every shape
  /// The hulls and the build's surfaces are checked at radius + this: the safety margin a planner
  /// adds (>= 0). Deep and clear segments stay defined at radius, against the truth.
  double margin = 0.0;
  /// A part is *false* when its hull comes no closer than this to any true obstacle (map units; the
  /// CLI's default is one voxel of the build, the resolution in obstacles.json).
  double false_tolerance = 0.05;
  std::size_t volume_samples = 4000;      ///< Monte Carlo points per part hull
  std::size_t segments = 2000;            ///< random segments in the free volume
  double segment_length = 2.0;            ///< segments are 0.2 .. this long
  SegmentEnds ends = SegmentEnds::kFree;  ///< where the endpoints are drawn
  std::vector<Eigen::Vector3d> path;      ///< kCorridor: the camera's keyframes in order (map frame), >= 1
  double corridor_width = 10.0;           ///< kCorridor: reach of the corridor in (x, y) from the path, > 0
  double corridor_height = 3.0;           ///< kCorridor: how far above the nearest keyframe ends may lie, > 0
  /// A deep segment is unseen (Evaluation::deep_unseen) when its capsule holds fewer map points than
  /// this (the points' weights summed: a voxel centre weighs its map points).
  double seen_points = 3.0;
  double sample_step = 0.01;  ///< spacing of the truth's distance samples along a segment
  std::uint64_t seed = 1;
};

/// Per true obstacle.
struct TruthScore {
  std::string label;
  bool surface = false;  ///< a floor, ceiling or height field (TruthShape::surface)
  /// Weight of its observed points: map points whose nearest shape surface is this one's, within
  /// surface_margin (each point counts for one shape only).
  double points_near = 0;
  double points_inside = 0;  ///< of those, inside some hull
  /// The hulls that represent it, (obstacle id, part index; -1 whole hull): each hull represents at
  /// most one shape (docs/DESIGN_NOTES.md, "evaluate.hpp: represented parts").
  std::vector<std::pair<int, int>> parts;
  /// The hulls coming within touch_margin of it, whatever they represent: at a corner of two walls
  /// the end parts of both touch both walls, so this counts neighbours too.
  std::vector<std::pair<int, int>> parts_touching;
};

/// A hull farther than EvaluateParams::false_tolerance from every true obstacle: an obstacle where
/// the world has none (outlier voxels the clustering kept, as a rule).
struct FalsePart {
  int obstacle = 0;        ///< obstacle id
  int part = -1;           ///< its part; -1 a whole hull
  std::size_t voxels = 0;  ///< its voxels
  double volume = 0.0;     ///< its hull's volume, map units^3: the free space it brings
  /// Its hull's distance from the nearest true obstacle, map units: exact for boxes, cylinders and
  /// unions, sampled for meshes and height fields (docs/DESIGN_NOTES.md, "evaluate.hpp: FalsePart").
  double distance = 0.0;
};

/// A hull that false alarms hit: the hull checker's first contact on that many clear segments.
struct FalseAlarmHull {
  int obstacle = 0;  ///< obstacle id
  int part = -1;     ///< its part; -1 a whole hull
  std::size_t segments = 0;
};

/// A deep segment the hulls called clear: the truth shape it penetrates deepest, and how deep
/// (radius minus the truth's smallest sampled distance along it, map units).
struct MissedSegment {
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
  std::string truth;  ///< TruthShape::label
  double depth = 0.0;
  bool unseen = false;  ///< fewer than seen_points map points within radius of it (Evaluation::deep_unseen)
};

/// What evaluate() measures. Volumes in map units^3, each with its Monte Carlo standard error.
struct Evaluation {
  std::vector<TruthScore> truth;
  std::size_t parts = 0;                                 ///< hulls scored (parts, or whole obstacles without parts)
  std::vector<FalsePart> false_parts;                    ///< parts farther than false_tolerance from every shape
  double false_volume = 0.0;                             ///< their summed hull volume
  double hull_volume = 0.0;                              ///< summed part hull volume
  double union_volume = 0.0, union_volume_se = 0.0;      ///< volume of the union of the hulls
  double outside_volume = 0.0, outside_volume_se = 0.0;  ///< of the union, outside every shape
  double far_volume = 0.0, far_volume_se = 0.0;          ///< of the union, farther than far_margin
  std::size_t segments = 0;
  std::size_t deep = 0;    ///< segments whose capsule penetrates the truth by > depth_margin
  std::size_t missed = 0;  ///< of those, reported clear by the hull checker
  /// Deep segments whose capsule holds fewer than seen_points map points: places the map never saw
  /// (or saw as stray points; docs/DESIGN_NOTES.md, "evaluate.hpp: deep_unseen").
  std::size_t deep_unseen = 0;
  std::size_t missed_unseen = 0;  ///< of the missed, those unseen
  std::size_t clear = 0;          ///< segments keeping radius + clear_margin from the truth
  std::size_t false_alarms = 0;   ///< of those, reported colliding
  /// The hulls the false alarms hit first, most hit first (ties by obstacle id, then part).
  std::vector<FalseAlarmHull> false_alarm_hulls;
  std::vector<MissedSegment> missed_segments;  ///< every missed one, in the order drawn
};

/// Scores the obstacles (their parts when they have some, else their whole hulls) against the
/// truth. `points` (map frame) with `weights` (empty: 1 each) are the map's points; each one within
/// surface_margin of some shape is an observed point of the nearest shape only (see
/// EvaluateParams::surface_margin), and each hull represents the shape owning most of the observed
/// points inside it (TruthScore::parts).
/// Segments: endpoints drawn uniformly in the box of the truth grown by radius + clear_margin + 0.5
/// until both keep radius + clear_margin from the truth (from their own random stream: the same
/// segments whatever the obstacles, so two builds are scored on the same ones); the truth's smallest distance along a
/// segment is taken at spacing <= sample_step, which brackets the exact value within sample_step / 2 (distance is
/// 1-Lipschitz): a segment is deep or clear only when the bracket says so for certain, and neither
/// otherwise. The hull side is collision::HullChecker with `surfaces` (the build's floor and ceiling,
/// obstacles for checks as in `hullmap check`). Volumes: volume_samples uniform points in each
/// hull, a point counted for the union only in the first hull holding it.
Evaluation evaluate(const std::vector<hulls::Obstacle>& obstacles, const GroundTruth& truth,
                    const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint32_t>& weights,
                    const EvaluateParams& params, const std::vector<collision::Surface>& surfaces = {});

/// The result as JSON: params, per truth shape, totals.
nlohmann::json evaluationToJson(const Evaluation& evaluation, const EvaluateParams& params);

}  // namespace hullmap::sim
